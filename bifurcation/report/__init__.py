"""The report: figures (``figures``) and the Markdown/HTML document (``render``) built from stores."""

from .render import ReportData, analyse, write_report

__all__ = sorted(["ReportData", "analyse", "write_report"])
