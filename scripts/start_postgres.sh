#!/usr/bin/env bash
# Starts a local PostgreSQL server for the postgres-marked tests (distributed Optuna tuning) and
# prints the URL they use. Idempotent, and fast when the server already answers.
#
#   URL (fixed, local test credentials, nothing secret):
#     postgresql://sb3pnn:sb3pnn@127.0.0.1:5432/sb3pnn_test
#   Override with SB3_PNN_POSTGRES_URL (the tests read the same variable).
#
# Order: (1) the URL already answers -> done; (2) PostgreSQL is missing -> apt-get update and
# install it (Debian/Ubuntu, as root); (3) start it: as root with Debian's pg_ctlcluster (the
# packaged cluster), else as this user with initdb/pg_ctl in ${SB3_PNN_PGDATA:-~/.cache/sb3-pnn/pgdata};
# (4) create the role and database when absent.
set -euo pipefail

URL=${SB3_PNN_POSTGRES_URL:-postgresql://sb3pnn:sb3pnn@127.0.0.1:5432/sb3pnn_test}
# postgresql://USER:PASSWORD@HOST:PORT/DB
rest=${URL#postgresql://}
DB_USER=${rest%%:*}; rest=${rest#*:}
DB_PASS=${rest%%@*}; rest=${rest#*@}
DB_HOST=${rest%%:*}; rest=${rest#*:}
DB_PORT=${rest%%/*}; DB_NAME=${rest#*/}

answers() {
  PGPASSWORD="$DB_PASS" PGCONNECT_TIMEOUT=3 psql -h "$DB_HOST" -p "$DB_PORT" -U "$DB_USER" \
    -d "$DB_NAME" -tAc "select 1" >/dev/null 2>&1
}

if command -v psql >/dev/null 2>&1 && answers; then
  echo "$URL"
  exit 0
fi

find_bin() {  # a PostgreSQL server binary: on PATH, else the newest /usr/lib/postgresql/*/bin
  if command -v "$1" >/dev/null 2>&1; then command -v "$1"; return; fi
  ls -d /usr/lib/postgresql/*/bin/"$1" 2>/dev/null | sort -V | tail -n 1
}

if [ -z "$(find_bin initdb)" ] || ! command -v psql >/dev/null 2>&1; then
  if [ "$(id -u)" -ne 0 ] || ! command -v apt-get >/dev/null 2>&1; then
    echo "start_postgres.sh: PostgreSQL is not installed and apt-get as root is unavailable" >&2
    exit 1
  fi
  echo "Installing PostgreSQL (apt-get)..." >&2
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -qq >&2
  apt-get install -y -qq postgresql postgresql-client >&2
fi

as_admin() {  # run psql as the server's superuser over the local socket
  if [ "$(id -u)" -eq 0 ]; then
    (cd /tmp && runuser -u postgres -- psql -p "$DB_PORT" -v ON_ERROR_STOP=1 -tA "$@")
  else
    psql -h "${PGDATA_DIR}" -p "$DB_PORT" -d postgres -v ON_ERROR_STOP=1 -tA "$@"
  fi
}

wait_ready() {
  for _ in $(seq 1 60); do
    if pg_isready -h "$1" -p "$DB_PORT" -q 2>/dev/null; then return 0; fi
    sleep 0.5
  done
  echo "start_postgres.sh: the server did not become ready" >&2
  return 1
}

if [ "$(id -u)" -eq 0 ] && command -v pg_ctlcluster >/dev/null 2>&1; then
  cluster=$(pg_lsclusters -h 2>/dev/null | awk -v p="$DB_PORT" '$3 == p {print $1" "$2; exit}')
  if [ -z "$cluster" ]; then
    version=$(ls /usr/lib/postgresql | sort -V | tail -n 1)
    pg_createcluster -p "$DB_PORT" "$version" sb3pnn >&2
    cluster="$version sb3pnn"
  fi
  # shellcheck disable=SC2086
  pg_ctlcluster $cluster start >/dev/null 2>&1 || true
  wait_ready 127.0.0.1
else
  PGDATA_DIR=${SB3_PNN_PGDATA:-$HOME/.cache/sb3-pnn/pgdata}
  PATH="$(dirname "$(find_bin initdb)"):$PATH"
  if [ ! -f "$PGDATA_DIR/PG_VERSION" ]; then
    mkdir -p "$PGDATA_DIR"
    initdb -D "$PGDATA_DIR" -A scram-sha-256 --auth-local=trust -U "$(id -un)" >/dev/null
  fi
  if ! pg_ctl -D "$PGDATA_DIR" status >/dev/null 2>&1; then
    pg_ctl -D "$PGDATA_DIR" -l "$PGDATA_DIR/server.log" -w \
      -o "-p $DB_PORT -k $PGDATA_DIR -c listen_addresses=127.0.0.1" start >&2
  fi
  wait_ready 127.0.0.1
fi

if [ "$(as_admin -c "select 1 from pg_roles where rolname = '$DB_USER'")" != "1" ]; then
  as_admin -c "create role \"$DB_USER\" login password '$DB_PASS'" >/dev/null
fi
if [ "$(as_admin -c "select 1 from pg_database where datname = '$DB_NAME'")" != "1" ]; then
  as_admin -c "create database \"$DB_NAME\" owner \"$DB_USER\"" >/dev/null
fi

if ! answers; then
  echo "start_postgres.sh: the server runs but $DB_USER@$DB_HOST:$DB_PORT/$DB_NAME does not answer" >&2
  exit 1
fi
echo "$URL"
