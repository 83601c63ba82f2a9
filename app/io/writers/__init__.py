"""Samples written out: a recording's rows, calibrated or passed through, as CSV, Parquet or ``.npy``, a chunk at a
time (:mod:`.samples`). Each column's name carries its unit, as trical's readers recognise it (``acc_x (m/s^2)``,
``gyr_x (rad/s)``, ``mag_x (uT)``, ``time (s)``, ``temp_c``)."""
