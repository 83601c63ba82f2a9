"""The response models of /api/v1/links: a calibration's short-lived link and what opening it gives."""

from __future__ import annotations

from pydantic import BaseModel, Field


class LinkOut(BaseModel):
    code: str = Field(description="Ten letters and digits, typed or scanned on the other device.")
    calibration_id: str
    created_at: str
    expires_at: str = Field(description="After this (TRICAL_LINK_TTL_MIN from its making) the link reads nothing.")
    url: str = Field(description="The link's page, /s/CODE, on this server.")
    qr: str = Field(description="The QR code of url, an SVG data: URI.")


class LinkOpened(BaseModel):
    code: str
    calibration_id: str
    expires_at: str
    token: str = Field(
        description="`Authorization: Bearer` value that reads this calibration (and no other) until expires_at."
    )
