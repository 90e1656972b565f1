"""The gateway's plain HTTP routes: the REST front forwarded to the services, /readyz and /metrics, the web
console and the Lab's page."""
