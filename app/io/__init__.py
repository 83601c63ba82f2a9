"""Log readers and calibration exporters: files in, arrays out; results in, files out."""
