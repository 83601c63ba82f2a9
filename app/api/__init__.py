"""The REST API (v1): routers, schemas, dependencies and the error mapping."""

from fastapi import APIRouter

from . import calibrations, health, links, recordings, sessions

router = APIRouter()
for module in (health, calibrations, links, recordings, sessions):
    router.include_router(module.router)
