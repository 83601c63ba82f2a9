"""A board's live lines: what boards print over a serial port or a Bluetooth UART, read as they arrive.

:mod:`.formats` holds the constants of the board connection (MotionCal's ``Raw:`` and Adafruit's ``Uni:`` lines,
the baud rates, the rate's rule, the Nordic UART Service, the facts of MotionCal's calibration packet), which the
terminal and the page both read; :mod:`.lines` reads the lines a board prints (the format recognised from the first
lines, each line a reading stamped with its arrival and the board's own time), counts the board's rate, and writes
the readings as a log that the readers read back. Nothing here opens a port. The packet a board is sent is an export
(:mod:`app.io.exports.motioncal_packet`).
"""
