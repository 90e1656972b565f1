"""Who may do what at the gateway: tokens (stored, static or JWT) and their scopes, the tool policy (profiles,
allow/deny globs, the lean listing a profile may ask for), REST routes under the same policy, per-token rate
limits and upload limits. Imports nothing else of the gateway, so the other rooms may all use it."""
