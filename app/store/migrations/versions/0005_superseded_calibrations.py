"""A calibration of the same recording (its upload's content) and method supersedes the earlier ones:
each calibration keeps its recording's digest, and the earlier ones name the one that superseded them
(nothing is deleted). Calibrations stored before keep no digest and supersede nothing.

Revision ID: 0005
Revises: 0004
"""

from __future__ import annotations

import sqlalchemy as sa
from alembic import op

revision = "0005"
down_revision = "0004"
branch_labels = None
depends_on = None


def upgrade() -> None:
    with op.batch_alter_table("calibrations") as batch:
        batch.add_column(sa.Column("recording_digest", sa.Text))
        batch.add_column(sa.Column("superseded_by", sa.Text))
    op.create_index("calibrations_recording", "calibrations", ["recording_digest", "method"])
    op.create_index("calibrations_superseded", "calibrations", ["superseded_by"])


def downgrade() -> None:
    op.drop_index("calibrations_superseded", "calibrations")
    op.drop_index("calibrations_recording", "calibrations")
    with op.batch_alter_table("calibrations") as batch:
        batch.drop_column("superseded_by")
        batch.drop_column("recording_digest")
