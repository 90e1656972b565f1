"""bagmcp's service kit: the MCP-side pieces every service shares (answers, arguments, long work,
the jobs tools, caller identity, the service app factory)."""
