"""ORCCAD section 6: design rules, schedulability, chain latency, port repair,
fixed-priority timelines, and the design section of a report."""
