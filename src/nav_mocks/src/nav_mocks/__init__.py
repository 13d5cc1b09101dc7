"""Map server / GMapping, AMCL and move_base stand-ins with the real ROS interfaces."""
