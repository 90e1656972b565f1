"""bagmcp gateway: the single ingress (aggregated MCP endpoint, REST front, health); it knows no service."""
