"""The web front end every app shares: static assets (the shared views, the console, the vendored uPlot),
pages served with a strict Content-Security-Policy, and the MCP Apps viewer documents. No service code:
the gateway serves the console, the services serve the viewers, both from these files."""
