"""Liveness."""

from fastapi import APIRouter

from app.api.schemas.health import Health

router = APIRouter(tags=["health"])


@router.get("/healthz", response_model=Health, summary="Liveness")
def healthz() -> dict[str, str]:
    """`{"status": "ok"}` while the service answers."""
    return {"status": "ok"}
