"""MCP Lab: run models on bag questions over the gateway's MCP endpoint and judge their answers against the
tools' own (``bagmcp lab run``, ``bagmcp lab report``, the ``/lab`` page)."""
