"""The results store: Zarr v3 through xarray, one chunk per tile, resumable (``done`` mask)."""

from .catalog import read_catalog
from .layout import DIMS, STORE_FORMAT, VARIABLES
from .zarr_store import (check_store, create_store, open_store, read_attrs, read_done, record_submit,
                         store_kind, write_tile)

__all__ = ["DIMS", "STORE_FORMAT", "VARIABLES", "check_store", "create_store", "open_store",
           "read_attrs", "read_catalog", "read_done", "record_submit", "store_kind", "write_tile"]
