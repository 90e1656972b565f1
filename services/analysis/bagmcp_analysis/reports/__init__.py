"""Output schemas of the analysis tools, one module per area."""
