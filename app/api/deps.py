"""Dependencies shared by the routers: settings and the store, held on the application."""

from fastapi import Request

from app.config import Settings
from app.store import SQLiteStore


def get_settings(request: Request) -> Settings:
    return request.app.state.settings


def get_store(request: Request) -> SQLiteStore:
    return request.app.state.store
