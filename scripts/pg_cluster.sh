#!/usr/bin/env bash
# A throwaway PostgreSQL cluster for vx worlds (benchmarks, trying shared worlds by hand):
#   bash scripts/pg_cluster.sh start DIR   # initdb + start on a Unix socket in DIR; prints a world URI
#   bash scripts/pg_cluster.sh stop DIR    # stop it (then rm -rf DIR)
# No TCP port is opened. initdb refuses root: as root the server runs as `nobody`.
set -euo pipefail
cmd=${1:-}; dir=${2:-}
[[ -n "$cmd" && -n "$dir" ]] || { echo "usage: scripts/pg_cluster.sh start|stop DIR" >&2; exit 2; }
bin=$(ls -d /usr/lib/postgresql/*/bin 2>/dev/null | sort -V | tail -1)
[[ -x "$bin/initdb" ]] || { echo "pg_cluster: PostgreSQL server not installed (apt-get install postgresql)" >&2; exit 2; }
as_owner() { if [[ $(id -u) -eq 0 ]]; then setpriv --reuid=nobody --regid=nogroup --clear-groups "$@"; else "$@"; fi; }
dir=$(realpath -m "$dir")
case "$cmd" in
  start)
    mkdir -p "$dir"; chmod 777 "$dir"
    [[ $(id -u) -eq 0 ]] && chown nobody:nogroup "$dir"
    if [[ ! -d "$dir/data" ]]; then
      as_owner "$bin/initdb" -D "$dir/data" -A trust -U vx -E UTF8 --locale=C >"$dir/initdb.log"
    fi
    as_owner "$bin/pg_ctl" -D "$dir/data" -l "$dir/log" -w -o "-k $dir -c listen_addresses=" start >/dev/null
    psql -q "postgresql:///postgres?host=$dir&user=vx" -c "CREATE DATABASE vxworld" 2>/dev/null || true
    echo "postgresql:///vxworld?host=$dir&user=vx"
    ;;
  stop) as_owner "$bin/pg_ctl" -D "$dir/data" -m fast -w stop >/dev/null ;;
  *) echo "usage: scripts/pg_cluster.sh start|stop DIR" >&2; exit 2 ;;
esac
