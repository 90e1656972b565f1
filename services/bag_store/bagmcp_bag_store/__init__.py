"""bagmcp bag-store: owns bags (catalog, upload, ingest) and serves their messages."""
