"""Flight controllers' logs and the flight around their compass.

The readers of the two firmwares' logs, PX4's ULog (:mod:`.ulog`, through pyulog) and ArduPilot's DataFlash
(:mod:`.dataflash`, through pymavlink), turn every IMU and compass instance into a stream; :mod:`.instances` picks the
ones asked and puts them on one clock (:func:`app.io.readers.read_log` reads a flight log through them). A compass
from a flight is read with its context (:mod:`.compass`): the firmware's part (:mod:`.ardupilot`, :mod:`.px4`) over
what both share (:mod:`.context`: the stored calibration, the attitude, the power, the first GPS fix).
"""
