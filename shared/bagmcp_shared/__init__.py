"""bagmcp_shared: the library every bagmcp service uses (bags, paths, time, storage, errors)."""
