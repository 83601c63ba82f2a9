"""The ``trical`` command: its entry (``main``), its parser, one module per command family, the printers and
the capture on a serial port (``board``)."""
