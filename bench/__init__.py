"""The benchmark: every tool timed as an MCP client sees it (calls over HTTP with the official client),
embedded and through the local stack's gateway, on generated ~2 GB drives in the three bag formats,
next to the rosbags decode floor of the same work. ``python -m bench [--quick]`` writes BENCHMARKS.md."""
