"""Learning side of direction following: phrase sets, route oracle, floors, expert
demonstrations, training, DAgger and closed-loop evaluation (ROS-free; the runtime is
semantic_nav).
"""
