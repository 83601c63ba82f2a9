"""Log readers and calibration exporters: files in, arrays out; results in, files out.

One room per job: :mod:`.readers` (``read_log`` and the app formats' readers over one CSV stack, the rate, units,
sign, arrays, wearables, recordings in several files), :mod:`.flight` (flight controllers' logs, and a compass read
with its flight's context), :mod:`.exports` (a stored calibration as files and pictures) and :mod:`.board` (a board's
live lines). What they all share stays here: :mod:`.errors`, :mod:`.log` (``LogData`` and the unit tables) and
:mod:`.plural`.
"""
