"""The read options a command's flags give (:func:`read_options`): every command that reads a file takes the same
flags for it (``parser._read_options``), so each builds its :class:`~app.io.readers.read_options.ReadOptions` here."""

from __future__ import annotations

import argparse

from app.io.readers.read_options import ReadOptions


def read_options(args: argparse.Namespace, *, units: dict | None, clock: str = "imu") -> ReadOptions:
    """The options the file is read with: the flags of ``_read_options`` and ``--sampling-rate-hz`` (which every
    reading command has), ``--lsb-per-g`` and ``--mag-instance`` where the command has them, and ``units`` as the
    command decides them from its unit flags."""
    return ReadOptions(
        format=args.log_format,
        sampling_rate_hz=args.sampling_rate_hz,
        units=units,
        lsb_per_g=getattr(args, "lsb_per_g", None),
        columns=args.columns,
        sign=args.sign,
        chip=args.chip,
        instance=args.instance,
        mag_instance=getattr(args, "mag_instance", None),
        clock=clock,
    )
