"""Prometheus metrics of the gateway: calls and errors per tool and upstream, call latency, upstream state."""

from __future__ import annotations

from prometheus_client import CollectorRegistry, Counter, Gauge, Histogram, generate_latest
from prometheus_client.exposition import CONTENT_TYPE_LATEST

LATENCY_BUCKETS_S = (0.002, 0.005, 0.01, 0.025, 0.05, 0.1, 0.25, 0.5, 1, 2.5, 5, 10, 30, 60)


class GatewayMetrics:
    """Its own registry, so several gateways (tests, replicas in one process) never share counters."""

    content_type = CONTENT_TYPE_LATEST

    def __init__(self) -> None:
        self.registry = CollectorRegistry()
        self.calls = Counter(
            "bagmcp_gateway_calls", "Tool calls", ["tool", "upstream", "outcome"], registry=self.registry
        )
        self.latency = Histogram(
            "bagmcp_gateway_call_seconds",
            "Tool call duration through the gateway",
            ["tool", "upstream"],
            buckets=LATENCY_BUCKETS_S,
            registry=self.registry,
        )
        self.upstream_up = Gauge(
            "bagmcp_gateway_upstream_up", "1 when the upstream answers", ["upstream"], registry=self.registry
        )

    def record(self, tool: str, upstream: str, outcome: str, seconds: float) -> None:
        self.calls.labels(tool, upstream, outcome).inc()
        if outcome in ("ok", "error"):
            self.latency.labels(tool, upstream).observe(seconds)

    def exposition(self) -> bytes:
        return generate_latest(self.registry)
