"""Hostile uploads: truncated, binary, huge lines, a million columns — a 4xx, never a 500."""

from __future__ import annotations

import numpy as np
import pytest

from tests.api.test_recordings import LOG, upload


def truncated() -> bytes:
    data = LOG.read_bytes()
    return data[: len(data) // 2 + 7]  # cut in the middle of a line


CASES = {
    "truncated": truncated,
    "random_binary": lambda: np.random.default_rng(7).integers(0, 256, 200_000, dtype=np.uint8).tobytes(),
    "latin1_text": lambda: "acc_x,acc_y,acc_z\n1,2,3\n\xe9\xe8,1,2\n".encode("latin-1"),
    "huge_line": lambda: b"acc_x,acc_y,acc_z\n" + b"1" * 20_000_000 + b",2,3\n",
    "million_columns": lambda: ",".join(f"c{i}" for i in range(1_000_000)).encode() + b"\n",
    "million_columns_acc": lambda: (
        b"acc_x,acc_y,acc_z,"
        + b",".join(b"c%d" % i for i in range(1_000_000))
        + b"\n"
        + b"1,2,3,"
        + b",".join(b"0" for _ in range(1_000_000))
        + b"\n"
    ),
    "only_newlines": lambda: b"\n" * 100_000,
    "ragged_rows": lambda: b"acc_x,acc_y,acc_z\n1,2,3\n1,2\n1,2,3,4,5\n",
    "nan_values": lambda: b"acc_x,acc_y,acc_z\n1,2,3\nnan,2,3\n",
    "quoted_header": lambda: b'"acc_x","acc_y","acc_z"\n"1","2","3"\n',
}


@pytest.mark.parametrize("name", sorted(CASES))
def test_hostile_upload_gets_a_4xx_or_a_clean_201(client, name):
    r = upload(client, CASES[name](), sampling_rate_hz=100)
    assert r.status_code < 500, (name, r.status_code, r.text[:300])
    if r.status_code >= 400:
        detail = r.json()["detail"]
        assert isinstance(detail, str) and 10 < len(detail) < 2000, detail
    else:
        assert r.json()["n_samples"] >= 1
