"""Drives you can buy: a motor-gearbox catalogue (MGDB's CSV format) and the choice of a drive
that meets a joint's duty (torque-speed envelope, RMS torque, gearbox ratings).

Units are SI throughout: N m, rad/s, s, kg, kg m^2.
"""
