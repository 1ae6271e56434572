#!/usr/bin/env bash
# Issue 12's first-contact check: a fresh Debian 12 root (debootstrap minbase plus what a new
# user has: ca-certificates, git, gcc, libc6-dev, pkg-config, sudo) with only rustup's toolchain
# copied in (and the host's CA bundle: TLS is re-signed on these machines), a fresh clone, then
# the README's commands: `cargo xtask run` (no display: the headless fallback) and
# `cargo xtask test --quick`. Run as root on the host; ROOT and the clone's source may be set.
set -euo pipefail
ROOT=${ROOT:-/var/tmp/vr-ocean-fresh}
SRC=${SRC:-$(cd "$(dirname "$0")/../.." && pwd)}
MIRROR=${MIRROR:-http://deb.debian.org/debian}
say() { echo "== $(date +%H:%M:%S) $*"; }

if [ ! -x "$ROOT/usr/bin/git" ]; then
    say "debootstrap bookworm into $ROOT"
    rm -rf "$ROOT"
    debootstrap --variant=minbase \
        --include=ca-certificates,git,gcc,libc6-dev,pkg-config,sudo \
        bookworm "$ROOT" "$MIRROR" > /tmp/fresh-debootstrap.log 2>&1
fi
say "the host's CA bundle and rustup's toolchain"
cp /etc/ssl/certs/ca-certificates.crt "$ROOT/etc/ssl/certs/ca-certificates.crt"
mkdir -p "$ROOT/root/.rustup/toolchains" "$ROOT/root/.cargo/bin"
cp -a /root/.rustup/settings.toml "$ROOT/root/.rustup/"
[ -d "$ROOT/root/.rustup/toolchains/stable-x86_64-unknown-linux-gnu" ] ||
    cp -a /root/.rustup/toolchains/stable-x86_64-unknown-linux-gnu "$ROOT/root/.rustup/toolchains/"
cp -a /root/.cargo/bin/. "$ROOT/root/.cargo/bin/"
cat > "$ROOT/root/.cargo/env" <<'ENV'
export PATH="$HOME/.cargo/bin:$PATH"
ENV

say "a fresh clone (of $(git -C "$SRC" rev-parse --short HEAD))"
rm -rf "$ROOT/root/vr-ocean"
git clone -q "$SRC" "$ROOT/root/vr-ocean"

for m in proc sys dev dev/pts; do
    mountpoint -q "$ROOT/$m" || mount --bind "/$m" "$ROOT/$m"
done
trap 'for m in dev/pts dev sys proc; do umount "$ROOT/$m" 2>/dev/null || true; done' EXIT

in_root() {
    chroot "$ROOT" env -i HOME=/root TERM=dumb LANG=C.UTF-8 \
        PATH=/root/.cargo/bin:/usr/local/sbin:/usr/local/bin:/usr/sbin:/usr/bin:/sbin:/bin \
        bash -c "cd /root/vr-ocean && $1"
}
say "cargo xtask run"
in_root "cargo xtask run" 2>&1 | tee /tmp/fresh-run.log | grep -vE '^\s+(Compiling|Downloaded|Fetching) ' | tail -40
say "cargo xtask test --quick"
in_root "cargo xtask test --quick" 2>&1 | tee /tmp/fresh-test.log | grep -vE '^\s+(Compiling|Downloaded|Fetching) |^(Get|Unpacking|Selecting|Preparing|Setting up)' | tail -60
say "done"
