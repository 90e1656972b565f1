#!/usr/bin/env bash
# Certificates for the gRPC ports of the S3 server (weed) of `make stack` and of the tests: weed's master, volume
# server, filer and S3 gateway talk gRPC to each other, and without TLS anyone on the machine could call them
# (e.g. delete a collection, which holds every bag). With these, every gRPC port asks for a client certificate
# signed by the stack's own CA, whose key is deleted once the one certificate is signed (nobody can sign
# another). Made once per directory: deploy/stack/weed-tls.sh DIR writes DIR/ca.crt, DIR/node.crt, DIR/node.key.
set -euo pipefail
umask 077
tls="$1"
[ -s "$tls/node.crt" ] && [ -s "$tls/node.key" ] && [ -s "$tls/ca.crt" ] && exit 0
command -v openssl >/dev/null || { echo "weed-tls: openssl is needed to make the S3 server's certificates" >&2; exit 1; }
mkdir -p "$tls"
ec=(-newkey ec -pkeyopt ec_paramgen_curve:P-256 -nodes)
openssl req -x509 "${ec[@]}" -keyout "$tls/ca.key" -out "$tls/ca.crt" -days 3650 -subj "/CN=bagmcp stack CA" 2>/dev/null
openssl req "${ec[@]}" -keyout "$tls/node.key" -out "$tls/node.csr" -subj "/CN=bagmcp stack" 2>/dev/null
printf 'subjectAltName=IP:127.0.0.1,DNS:localhost\nextendedKeyUsage=serverAuth,clientAuth\n' > "$tls/node.ext"
openssl x509 -req -in "$tls/node.csr" -CA "$tls/ca.crt" -CAkey "$tls/ca.key" -CAcreateserial -days 3650 \
  -extfile "$tls/node.ext" -out "$tls/node.crt" 2>/dev/null
rm -f "$tls/ca.key" "$tls/ca.srl" "$tls/node.csr" "$tls/node.ext"
