"""API tokens: records (kept only as hashes), their stores (a file when embedded, Redis for a team),
verification (API tokens and, optionally, JWTs from an identity provider) and the admin routes."""
