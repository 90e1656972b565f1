"""The analyses behind the tools: read what they need from a bag (index first), compute, report."""
