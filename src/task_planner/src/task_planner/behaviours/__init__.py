"""The TAMP executor's behaviours (ROS-free) and the behaviour tree that composes them
(task_planner.behaviours.tree). Each module is one behaviour over the shared Context: its
functions and the py_trees leaves that run them."""
