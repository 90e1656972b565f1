#!/usr/bin/env bash
# The Redis of `make stack`: loopback only, with the stack's password, and an append-only file so the
# catalog, jobs and queues survive a restart. Its process title stays as started: Redis would write the title
# over its environment, where the supervisor's member mark finds the stack's processes after a crash.
set -euo pipefail
umask 077
dir="$BAGMCP_STACK_DIR/redis"
mkdir -p "$dir"
cat > "$dir/redis.conf" <<CONF
port $REDIS_PORT
bind 127.0.0.1
requirepass $BAGMCP_REDIS_PASSWORD
dir $dir
save ""
appendonly yes
appendfsync everysec
set-proc-title no
CONF
exec redis-server "$dir/redis.conf"
