#!/usr/bin/env bash
# The limit study across machines (python3 -m study sweep --sshloginfile): the test starts two OpenSSH
# servers on loopback ports (127.0.0.1 and 127.0.0.2, its own host and user keys, key login
# only), lists them in an sshloginfile and runs python3 -m study sweep --test through them. Every job
# must have run on one of the two ssh hosts (the joblog's Host column), both hosts must have had
# work, and every job's output (stats JSON, image, log) must have come back into the shared run
# directory and into the CSV. Needs sshd and ssh (tools/setup.sh: openssh-server).
# Usage: remote_sweep_test.sh HRPP_BINARY WORK_DIR
set -euo pipefail
HRPP="${1:?usage: remote_sweep_test.sh HRPP_BINARY WORK_DIR}"
WORK="${2:?usage: remote_sweep_test.sh HRPP_BINARY WORK_DIR}"
REPO="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
SSHD=/usr/sbin/sshd
[[ -x "$SSHD" ]] || { echo "remote_sweep_test: $SSHD missing (tools/setup.sh installs openssh-server)" >&2; exit 1; }
command -v ssh-keygen >/dev/null || { echo "remote_sweep_test: ssh-keygen missing" >&2; exit 1; }
rm -rf "$WORK"
mkdir -p "$WORK"
WORK="$(cd "$WORK" && pwd)"

pids=()
cleanup() { for p in "${pids[@]}"; do kill "$p" 2>/dev/null || true; done; }
trap cleanup EXIT

ssh-keygen -q -t ed25519 -N '' -f "$WORK/host_key"
ssh-keygen -q -t ed25519 -N '' -f "$WORK/user_key"
cp "$WORK/user_key.pub" "$WORK/authorized_keys"
chmod 600 "$WORK/authorized_keys"
# sshd as root checks its privilege-separation directory; as another user it runs without one.
[[ "$(id -u)" != 0 ]] || mkdir -p /run/sshd

free_port() {
    /usr/bin/python3 -c 'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])'
}

: > "$WORK/sshloginfile"
hosts=(127.0.0.1 127.0.0.2)
for i in 0 1; do
    host="${hosts[$i]}"
    port="$(free_port)"
    cat > "$WORK/sshd_$i.conf" <<EOF
ListenAddress $host:$port
HostKey $WORK/host_key
AuthorizedKeysFile $WORK/authorized_keys
PidFile $WORK/sshd_$i.pid
StrictModes no
UsePAM no
PasswordAuthentication no
KbdInteractiveAuthentication no
PermitRootLogin prohibit-password
AcceptEnv HRPP_* VK_*
EOF
    "$SSHD" -D -e -f "$WORK/sshd_$i.conf" 2> "$WORK/sshd_$i.log" &
    pids+=($!)
    # One render at a time per host (1/); GNU parallel takes the ssh command from the line.
    echo "1/ssh -p $port -i $WORK/user_key -o BatchMode=yes -o StrictHostKeyChecking=no -o UserKnownHostsFile=/dev/null -o LogLevel=ERROR $host" >> "$WORK/sshloginfile"
done

# Wait until both servers answer a login (a few seconds at most).
for i in 0 1; do
    login="$(sed -n "$((i + 1))p" "$WORK/sshloginfile")"
    login="${login#1/}"
    for _ in $(seq 50); do
        if $login true 2>/dev/null; then continue 2; fi
        sleep 0.2
    done
    echo "remote_sweep_test: ssh server $i did not accept a login:" >&2
    cat "$WORK/sshd_$i.log" >&2
    exit 1
done

/usr/bin/python3 "$REPO/study" sweep --test --hrpp "$HRPP" --out "$WORK/run" --csv "$WORK/test.csv" \
    --figures "$WORK/figures" --sshloginfile "$WORK/sshloginfile" --grids test

/usr/bin/python3 - "$WORK" <<'PY'
import csv, json, os, sys
work = sys.argv[1]
logins = [l.strip()[2:] for l in open(os.path.join(work, "sshloginfile")) if l.strip()]
jobs = [json.loads(l) for l in open(os.path.join(work, "run", "jobs.jsonl"))]
log = list(csv.DictReader(open(os.path.join(work, "run", "joblog")), delimiter="\t"))
assert len(log) == len(jobs) == 4, f"{len(log)} joblog rows for {len(jobs)} jobs"
assert all(r["Exitval"] == "0" for r in log), log
hosts = [r["Host"] for r in log]
assert all(h in logins for h in hosts), f"jobs ran on {hosts}, not on the ssh hosts {logins}"
assert len(set(hosts)) == 2, f"only one ssh host had work: {hosts}"
runs = os.path.join(work, "run", "runs")
for j in jobs:
    for ext in (".json", ".exr", ".log"):
        p = os.path.join(runs, j["id"] + ext)
        assert os.path.isfile(p) and os.path.getsize(p) > 0, f"{p}: did not come back"
    json.load(open(os.path.join(runs, j["id"] + ".json")))
rows = list(csv.DictReader(open(os.path.join(work, "test.csv"))))
assert sorted(r["id"] for r in rows) == sorted(j["id"] for j in jobs), rows
assert all(r["ok"] == "1" for r in rows), rows
for i in range(2):
    accepted = open(os.path.join(work, f"sshd_{i}.log")).read().count("Accepted publickey")
    assert accepted > 0, f"ssh server {i} logged no login"
names = sorted(h.split()[-1] for h in set(hosts))
print(f"remote_sweep_test: {len(jobs)} jobs over ssh on {names}, every output back")
PY
