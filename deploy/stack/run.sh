#!/usr/bin/env bash
# `make stack`: redis-server, the S3 server, the three services, their workers and the gateway as local processes,
# with the same commands and BAGMCP_* environment docker-compose.yml gives them. Ctrl-C stops all.
set -euo pipefail
cd "$(dirname "$0")/../.."
export PATH="$PWD/.venv/bin:$PATH"
export BAGMCP_STACK_DIR="$(realpath -m "${BAGMCP_STACK_DIR:-.stack}")"
export GATEWAY_PORT="${GATEWAY_PORT:-8080}" BAG_STORE_PORT="${BAG_STORE_PORT:-8001}"
export ANALYSIS_PORT="${ANALYSIS_PORT:-8002}" PLOTTING_PORT="${PLOTTING_PORT:-8003}"
export REDIS_PORT="${REDIS_PORT:-6390}" S3_PORT="${S3_PORT:-8333}"
export BAGMCP_DEV_TOKEN="${BAGMCP_DEV_TOKEN:-bagmcp-dev-token}"
export BAGMCP_TOKENS="${BAGMCP_TOKENS:-$BAGMCP_DEV_TOKEN}"
export BAGMCP_SERVICE_TOKEN="${BAGMCP_SERVICE_TOKEN:-stack-service-$(id -u)-$(hostname)}"
export BAGMCP_S3_ACCESS_KEY="${BAGMCP_S3_ACCESS_KEY:-bagmcp}" BAGMCP_S3_SECRET_KEY="${BAGMCP_S3_SECRET_KEY:-bagmcp-stack-secret}"
export BAGMCP_S3_ENDPOINT="127.0.0.1:$S3_PORT" BAGMCP_S3_BUCKET="${BAGMCP_S3_BUCKET:-bagmcp}"
export BAGMCP_REDIS_URL="redis://127.0.0.1:$REDIS_PORT/0"
export BAGMCP_UPSTREAMS="bag-store=http://127.0.0.1:$BAG_STORE_PORT/mcp,analysis=http://127.0.0.1:$ANALYSIS_PORT/mcp,plotting=http://127.0.0.1:$PLOTTING_PORT/mcp"
export BAGMCP_REST_ROUTES="bags=http://127.0.0.1:$BAG_STORE_PORT,artifacts=http://127.0.0.1:$PLOTTING_PORT"
export BAGMCP_ARTIFACT_BASE_URL="http://127.0.0.1:$GATEWAY_PORT"
mkdir -p "$BAGMCP_STACK_DIR/redis"
echo "bagmcp stack: MCP at http://127.0.0.1:$GATEWAY_PORT/mcp, token $BAGMCP_DEV_TOKEN, data in $BAGMCP_STACK_DIR"
exec honcho -f deploy/stack/Procfile -d . start
