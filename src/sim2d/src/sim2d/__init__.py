"""Stage-like 2D simulator: world, kinematics, vectorised lasers, odometry, people, objects
and camera-level detections.
"""
