#!/usr/bin/env bash
# An ssh host on this machine, for the test of fvx batch plans run by GNU parallel on hosts
# reached by ssh (`parallel --sshlogin`):
#   scripts/sshd-local.sh start DIR   # an sshd on 127.0.0.1:6919; prints the ssh command for PARALLEL_SSH
#   scripts/sshd-local.sh stop DIR    # stops it, removes DIR
# Needs root and Debian's openssh-server (scripts/install-deps.sh). Host key, the client's key
# (root may log in with it only), configuration, pid file and log live in DIR; the port is
# not ssh's, so that an sshd on the machine is left alone.
set -euo pipefail

action=${1:-}
dir=${2:-}
[ -n "$action" ] && [ -n "$dir" ] || { echo "usage: sshd-local.sh start|stop DIR" >&2; exit 2; }
port=6919

stop() {
  [ -f "$dir/sshd.pid" ] && kill "$(cat "$dir/sshd.pid")" 2>/dev/null
  rm -rf "$dir"
}

start() {
  [ "$(id -u)" -eq 0 ] || { echo "sshd-local.sh: needs root (sshd runs its sessions as their users)" >&2; exit 1; }
  [ -x /usr/sbin/sshd ] || { echo "sshd-local.sh: /usr/sbin/sshd is missing (scripts/install-deps.sh)" >&2; exit 1; }
  mkdir -p "$dir" /run/sshd
  dir=$(cd "$dir" && pwd)
  ssh-keygen -q -t ed25519 -N '' -f "$dir/host_key"
  ssh-keygen -q -t ed25519 -N '' -f "$dir/id"
  cp "$dir/id.pub" "$dir/authorized_keys"
  cat > "$dir/sshd_config" <<CONF
Port $port
ListenAddress 127.0.0.1
HostKey $dir/host_key
AuthorizedKeysFile $dir/authorized_keys
PermitRootLogin prohibit-password
PasswordAuthentication no
KbdInteractiveAuthentication no
UsePAM no
StrictModes no
PidFile $dir/sshd.pid
CONF
  /usr/sbin/sshd -f "$dir/sshd_config" -E "$dir/sshd.log" ||
    { echo "sshd-local.sh: sshd did not start: $(tail -1 "$dir/sshd.log" 2>/dev/null)" >&2; exit 1; }
  local ssh="ssh -p $port -i $dir/id -o StrictHostKeyChecking=no -o UserKnownHostsFile=/dev/null -o BatchMode=yes -o LogLevel=ERROR"
  for _ in $(seq 1 50); do  # up to 10 s for it to answer
    if $ssh root@127.0.0.1 true 2>/dev/null; then
      echo "$ssh"
      return 0
    fi
    sleep 0.2
  done
  echo "sshd-local.sh: sshd does not answer on 127.0.0.1:$port: $(tail -1 "$dir/sshd.log" 2>/dev/null)" >&2
  exit 1
}

case "$action" in
  start) start ;;
  stop) stop ;;
  *) echo "usage: sshd-local.sh start|stop DIR" >&2; exit 2 ;;
esac
