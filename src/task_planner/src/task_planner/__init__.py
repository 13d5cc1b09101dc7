"""Decaying-reward instructions, topological graph, the seed's planner and baselines, and the
TAMP executor.
"""
