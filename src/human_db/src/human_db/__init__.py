"""SQLite human database (thesis 000 Table 3-1) with clothing-colour identification and
schedules.
"""
