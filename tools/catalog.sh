#!/usr/bin/env bash
# A private PostgreSQL 15 + PostGIS 3 cluster for the camera catalog (docs/catalog.md), the one the
# tests start (src/hv/io/native/camera_catalog_test.cpp) and one a user can start by hand:
#
#   tools/catalog.sh up   [--dir DIR] [--port PORT] [--owner-pid PID]
#   tools/catalog.sh down [--dir DIR]
#   tools/catalog.sh status [--dir DIR]
#
# `up` makes a cluster in DIR (initdb, once), starts it listening on 127.0.0.1:PORT only (its
# Unix socket in DIR, no other), creates the postgis extension in the `postgres` database and
# prints the connection on its last line: postgresql://postgres@127.0.0.1:PORT/postgres
# (trust authentication: only local users can reach it). `down` stops it and removes DIR.
# DIR defaults to ${TMPDIR:-/tmp}/histoview-catalog, PORT to 54320 (a free port when that is
# taken). With --owner-pid, a watcher stops the cluster and removes DIR once process PID is gone
# (the tests pass their own pid, so that a crashed test leaves no server behind). The environment
# variables HV_CATALOG_DIR, HV_CATALOG_PORT and HV_CATALOG_OWNER_PID give the same as the options.
#
# PostgreSQL refuses to run as root: as root (CI and the development machines run the tests as
# root), the server runs as the user HV_CATALOG_USER (default `nobody`) through runuser, and DIR
# belongs to that user. Needs postgresql-15 and postgresql-15-postgis-3 (tools/install-deps.sh).
set -euo pipefail

PG_BIN=${HV_PG_BIN:-/usr/lib/postgresql/15/bin}
cmd=${1:-}
shift || true
dir=${HV_CATALOG_DIR:-${TMPDIR:-/tmp}/histoview-catalog}
port=${HV_CATALOG_PORT:-}
owner=${HV_CATALOG_OWNER_PID:-}
while (($#)); do
  case $1 in
    --dir) dir=$2; shift 2 ;;
    --port) port=$2; shift 2 ;;
    --owner-pid) owner=$2; shift 2 ;;
    *) echo "catalog.sh: unknown option $1" >&2; exit 2 ;;
  esac
done

as_server() {  # runs a command as the user the server runs as
  if ((EUID == 0)); then runuser -u "${HV_CATALOG_USER:-nobody}" -- "$@"; else "$@"; fi
}

port_free() {
  ! (exec 3<>"/dev/tcp/127.0.0.1/$1") 2>/dev/null
}

case $cmd in
  up)
    if [[ ! -x $PG_BIN/initdb ]]; then
      echo "catalog.sh: $PG_BIN/initdb not found: install postgresql-15 and postgresql-15-postgis-3" >&2
      exit 3
    fi
    if [[ -z $port ]]; then
      port=54320
      while ! port_free "$port"; do port=$((port + 1)); done
    fi
    if [[ -f $dir/port ]] && as_server "$PG_BIN/pg_ctl" -D "$dir/data" status >/dev/null 2>&1; then
      echo "catalog.sh: already running in $dir" >&2
      echo "postgresql://postgres@127.0.0.1:$(cat "$dir/port")/postgres"
      exit 0
    fi
    mkdir -p "$dir"
    chmod 700 "$dir"
    if ((EUID == 0)); then chown "${HV_CATALOG_USER:-nobody}:" "$dir"; fi
    if [[ ! -f $dir/data/PG_VERSION ]]; then
      # --no-sync and fsync off: a scratch cluster, nothing in it must survive a power cut.
      as_server "$PG_BIN/initdb" -D "$dir/data" -U postgres -A trust -E UTF8 --no-locale --no-sync \
        >"$dir/initdb.log" 2>&1 || { cat "$dir/initdb.log" >&2; exit 1; }
    fi
    echo "$port" >"$dir/port"
    if ! as_server "$PG_BIN/pg_ctl" -D "$dir/data" -l "$dir/server.log" -w -t 30 \
      -o "-k $dir -h 127.0.0.1 -p $port -F -c fsync=off -c full_page_writes=off" start >/dev/null; then
      cat "$dir/server.log" >&2
      exit 1
    fi
    psql=(psql -X -q -v ON_ERROR_STOP=1 -h 127.0.0.1 -p "$port" -U postgres -d postgres)
    if ! "${psql[@]}" -c "CREATE EXTENSION IF NOT EXISTS postgis" >/dev/null; then
      as_server "$PG_BIN/pg_ctl" -D "$dir/data" -m immediate stop >/dev/null 2>&1 || true
      exit 1
    fi
    if [[ -n $owner ]]; then
      # The watcher: stops the cluster once the owner is gone, whatever way it went.
      (
        trap '' HUP
        while kill -0 "$owner" 2>/dev/null; do sleep 1; done
        as_server "$PG_BIN/pg_ctl" -D "$dir/data" -m immediate stop >/dev/null 2>&1 || true
        rm -rf "$dir"
      ) </dev/null >/dev/null 2>&1 &
      disown
    fi
    echo "postgresql://postgres@127.0.0.1:$port/postgres"
    ;;
  down)
    if [[ -d $dir/data ]]; then
      as_server "$PG_BIN/pg_ctl" -D "$dir/data" -m fast -w stop >/dev/null 2>&1 || true
    fi
    rm -rf "$dir"
    ;;
  status)
    if [[ -f $dir/port ]] && as_server "$PG_BIN/pg_ctl" -D "$dir/data" status >/dev/null 2>&1; then
      echo "running: postgresql://postgres@127.0.0.1:$(cat "$dir/port")/postgres"
    else
      echo "not running ($dir)"
      exit 1
    fi
    ;;
  *)
    sed -n '2,20p' "$0" >&2
    exit 2
    ;;
esac
