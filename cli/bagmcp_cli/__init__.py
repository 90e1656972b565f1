"""The bagmcp command: every service in one process (serve, stdio), upload, info, and the gateway."""
