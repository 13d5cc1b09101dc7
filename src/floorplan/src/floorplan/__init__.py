"""Map code shared by the runtime packages and the simulator: occupancy maps, semantic graphs,
blueprints, grid A* and map plots (ROS-free)."""
