"""The robot's memory of the household (thesis 000 §3.4, Table 3-1): a SQLite store with history
and schedules, and identification by shirt colour (§3.2.3, Algorithm 3-1).
"""
