"""Persistence of recordings and calibrations."""

from .sqlite import NotFoundError, SQLiteStore

__all__ = ["NotFoundError", "SQLiteStore"]
