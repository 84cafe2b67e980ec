"""The report: figures (``figures``) and the Markdown/HTML document built from stores: the paper's
reproduction (``render.write_report``, ``bifurcation reproduce``) and the report of any store
(``study.write_store_report``, ``bifurcation report``)."""

from .render import ReportData, analyse, write_report
from .study import write_store_report

__all__ = ["ReportData", "analyse", "write_report", "write_store_report"]
