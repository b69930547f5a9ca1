#!/usr/bin/env bash
# A throwaway PKI for the TLS tests, made at test time with openssl:
#   make-test-pki.sh DIR CN...
# writes into DIR (which must exist)
#   ca.pem, ca.key            the CA the broker and the terminals trust
#   other-ca.pem              a CA that signed nothing here (the "wrong CA")
#   server.pem, server.key    the broker: CN=localhost, SAN DNS:localhost, IP:127.0.0.1
#   server-expired.pem        the broker's key, certified for one day of 2020
#   <CN>.pem, <CN>.key        a client certificate per CN given (mutual TLS:
#                             the broker takes the CN as the user name)
#   <CN>-expired.pem          the same key, certified for one day of 2020
# `openssl ca` rather than `openssl x509 -req`: it dates a certificate in the
# past (-startdate/-enddate) on openssl 3.0 (Debian 12).
set -euo pipefail
dir=$1
shift
cd "$dir"

key() { openssl genpkey -algorithm EC -pkeyopt ec_paramgen_curve:prime256v1 -out "$1"; chmod 644 "$1"; }

key ca.key
openssl req -x509 -new -key ca.key -out ca.pem -days 3 -subj "/CN=nclink test CA"
key other-ca.key
openssl req -x509 -new -key other-ca.key -out other-ca.pem -days 3 -subj "/CN=nclink other CA"

mkdir -p ca.db
: > ca.db/index.txt
echo 01 > ca.db/serial
cat > ca.cnf <<'EOF'
[ca]
default_ca = test
[test]
dir = ./ca.db
database = $dir/index.txt
serial = $dir/serial
new_certs_dir = $dir
certificate = ca.pem
private_key = ca.key
default_md = sha256
policy = any
unique_subject = no
[any]
commonName = supplied
[server]
basicConstraints = CA:FALSE
subjectAltName = DNS:localhost,IP:127.0.0.1
extendedKeyUsage = serverAuth
[client]
basicConstraints = CA:FALSE
extendedKeyUsage = clientAuth
EOF

# cert NAME CN EXTENSIONS: NAME.pem (valid now) and NAME-expired.pem for NAME.key
cert() {
  key "$1.key"
  openssl req -new -key "$1.key" -subj "/CN=$2" -out "$1.csr"
  openssl ca -batch -config ca.cnf -extensions "$3" -days 3 -notext -in "$1.csr" -out "$1.pem"
  openssl ca -batch -config ca.cnf -extensions "$3" -startdate 20200101000000Z -enddate 20200102000000Z \
    -notext -in "$1.csr" -out "$1-expired.pem"
}

cert server localhost server
for cn in "$@"; do cert "$cn" "$cn" client; done
