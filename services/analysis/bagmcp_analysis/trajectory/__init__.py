"""Trajectory summaries: clock choice, distances, speeds, stops and waypoints."""
