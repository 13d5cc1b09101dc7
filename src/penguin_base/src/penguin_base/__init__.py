"""Differential-drive base of the Penguin: cmd_vel to wheels, odometry, watchdog, e-stop,
teleoperation, recorder.
"""
