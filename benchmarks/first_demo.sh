#!/usr/bin/env bash
# Benchmark "first_demo": the README's `make demo` on a fresh Debian 12 machine, timed from
# the clone to the last picture (issue 28's start-time target: <= 4 min with apt).
#
#     bash benchmarks/first_demo.sh [COMMIT]          (root; needs debootstrap and network)
#
# The fresh machine is a chroot: `debootstrap --variant=minbase bookworm` with git, make
# and ca-certificates (what a user needs to clone and type make), plus this host's extra CA
# certificates and /etc/pip.conf and its apt sources (a machine behind the same network
# proxy would have them too). Building it is not timed. Timed: `make demo` in a clone of
# this repository inside it: .ci/setup.sh (apt-get update and install of the Debian
# packages, the .venv, pip install of gsi and pyvista), then the full hopper-onto-membrane
# demo with empty numba and FFCx caches. The parts come from file times: the apt log, the
# venv's install stamp, the demo's picture.
#
# KEEP=1 keeps the root ($C) for a look. Last line: first_demo_s= apt_s= venv_pip_s=
# demo_s= rc=
# Record: python benchmarks/record.py first_demo -- bash benchmarks/first_demo.sh
set -u
REPO=$(cd "$(dirname "$0")/.." && pwd)
COMMIT=${1:-HEAD}
C=$(mktemp -d /var/tmp/gsi-first-demo.XXXXXX)
echo "building a fresh bookworm root in $C (not timed)"
debootstrap --variant=minbase --include=git,make,ca-certificates bookworm "$C" \
    http://deb.debian.org/debian > "$C.debootstrap.log" 2>&1 || {
    echo "error: debootstrap failed, see $C.debootstrap.log"; exit 1; }
rm -f "$C/etc/apt/sources.list"
cp /etc/apt/sources.list.d/*.sources "$C/etc/apt/sources.list.d/" 2>/dev/null || \
    cp /etc/apt/sources.list "$C/etc/apt/sources.list"
cp /etc/resolv.conf "$C/etc/resolv.conf"
cp /usr/local/share/ca-certificates/*.crt "$C/usr/local/share/ca-certificates/" 2>/dev/null
[ -f /etc/pip.conf ] && cp /etc/pip.conf "$C/etc/pip.conf"
chroot "$C" update-ca-certificates > /dev/null 2>&1
git clone -q "$REPO" "$C/root/gsi" && git -C "$C/root/gsi" checkout -q "$COMMIT"
mount -t proc proc "$C/proc"; mount -t sysfs sys "$C/sys"
mount --bind /dev "$C/dev"; mount --bind /dev/pts "$C/dev/pts"; mount -t tmpfs shm "$C/dev/shm"
start=$(date +%s.%N)
chroot "$C" /usr/bin/env -i HOME=/root TERM=dumb \
    PATH=/usr/local/sbin:/usr/local/bin:/usr/sbin:/usr/bin:/sbin:/bin \
    bash -c 'cd /root/gsi && make demo' > "$C.demo.log" 2>&1
rc=$?
end=$(date +%s.%N)
sleep 3
umount "$C/dev/shm" "$C/dev/pts"; umount "$C/dev" "$C/sys" "$C/proc"
tail -3 "$C.demo.log"
# the root is removed only when nothing is mounted in it any more (a bind mount of /dev!)
if [ -z "${KEEP:-}" ] && ! grep -q " $C/" /proc/mounts; then
    trap 'rm -rf "$C" "$C.debootstrap.log"' EXIT
fi
mt() { stat -c %.Y "$1" 2>/dev/null || echo nan; }
G=$C/root/gsi
apt_end=$(mt "$C/tmp/gsi-apt.log")
pip_end=$(mt "$G/.venv/.gsi-installed")
demo_end=$(mt "$G/out/hopper_membrane/hopper_membrane.png")
python3 - "$start" "$end" "$apt_end" "$pip_end" "$demo_end" "$rc" <<'EOF'
import sys
s, e, a, p, d, rc = (float(v) for v in sys.argv[1:])
print(f"first_demo_s={e - s:.1f} apt_s={a - s:.1f} venv_pip_s={p - a:.1f} "
      f"demo_s={d - p:.1f} rc={int(rc)}")
EOF
