#!/usr/bin/env bash
# `make stack`: redis-server, the S3 server, the three services, their workers and the gateway as local processes,
# with the same commands and BAGMCP_* environment docker-compose.yml gives them. Ports (the defaults when free)
# and secrets (random) are chosen on the first start and kept in $BAGMCP_STACK_DIR/stack.env (mode 0600). A
# process that dies is restarted; Ctrl-C stops all; the data in $BAGMCP_STACK_DIR stays.
#
# With arguments, runs that command with the settings of the stack instead, e.g.
#   deploy/stack/run.sh bagmcp catalog rebuild
set -euo pipefail
cd "$(dirname "$0")/../.."
export PATH="$PWD/.venv/bin:$PATH"
if [ $# -gt 0 ]; then
  settings="$(python -m bagmcp_cli.stack.environment command)"
  eval "$settings"
  exec "$@"
fi
settings="$(python -m bagmcp_cli.stack.environment start)"
eval "$settings"
echo "bagmcp stack: MCP at http://127.0.0.1:$GATEWAY_PORT/mcp, token $BAGMCP_DEV_TOKEN, data in $BAGMCP_STACK_DIR"
exec python -m bagmcp_cli.stack.supervisor deploy/stack/Procfile
