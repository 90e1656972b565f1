"""The gateway's side toward its upstream MCP servers: their configuration, the long-lived links (relay and
HTTP link for the stateless protocol), the tool catalog kept fresh in the background (change events shared
over Redis, readiness of the stores they need, their instructions merged), and where a resource read goes.
Imports nothing else of the gateway: it knows no caller."""
