"""bagmcp gateway: the single ingress (MCP endpoint, REST front) and the bagmcp command."""
