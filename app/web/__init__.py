"""Page routes rendering templates/."""

from .pages import router

__all__ = ["router"]
