"""The gateway's MCP endpoint as callers see it: the aggregated server, one tool call and one resource read
checked, limited, relayed in their wire form (answers capped), audited and counted. Built on ``upstreams``
(what there is to call) and ``access`` (who may call it)."""
