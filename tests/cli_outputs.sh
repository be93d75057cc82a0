#!/usr/bin/env bash
# cli_outputs.sh - what an output path names is written as that kind of file wants
# (src/core/atomic_file.h): a regular file replaced whole by rename, a symbolic link's target
# written with the link kept, a device or FIFO written through and never replaced, a FIFO with
# no reader refused at once, a directory refused. Every special file is made here in $work
# (mknod of a null and a full device where this machine allows it); none in /dev is touched.
# Usage: cli_outputs.sh RADIOSITY SOURCE_DIR
source "$(dirname "$0")/lib_cli.sh" "$@"
cd "$work"

small=(four-walls --solver jacobi --iterations 3 --quiet)

# The kind and inode of a path, not following a link: a replaced file shows as a change.
kind() { stat -c '%F %i' "$1"; }

# A regular file: replaced whole, permissions of the old file kept.
echo old >plain.csv
chmod 640 plain.csv
"$radiosity" solve "${small[@]}" --log plain.csv >stdout
check "regular file written" grep -q '^iteration,' plain.csv
check "regular file keeps its mode" test "$(stat -c %a plain.csv)" = 640
check "no temporary left beside it" test -z "$(ls -a | grep '\.tmp-')"

# A symbolic link: the link stays, its target gets the output; a dangling link's target is made.
echo old >target.csv
ln -s target.csv link.csv
"$radiosity" solve "${small[@]}" --log link.csv >stdout
check "link is still a link" test -L link.csv
check "link target written" grep -q '^iteration,' target.csv
mkdir sub
ln -s sub/made.svg dangling.svg
"$radiosity" solve "${small[@]}" --plot dangling.svg >stdout
check "dangling link still a link" test -L dangling.svg
check "dangling link target created" grep -q '<svg' sub/made.svg
ln -s loop-b loop-a && ln -s loop-a loop-b
expect_exit 1 'loop-a: cannot write: Too many levels of symbolic links' -- \
    "$radiosity" solve "${small[@]}" --log loop-a

# A FIFO with a reader gets the data and stays a FIFO; without one, an error at once.
mkfifo pipe.csv
before=$(kind pipe.csv)
timeout 20 cat pipe.csv >from-pipe.csv &
reader=$!
sleep 0.2
timeout 20 "$radiosity" solve "${small[@]}" --log pipe.csv >stdout
check "solve into a FIFO exits 0" test $? -eq 0
wait "$reader"
check "FIFO reader got the log" grep -q '^iteration,' from-pipe.csv
check "FIFO not replaced" test "$(kind pipe.csv)" = "$before"
expect_exit 1 'pipe.csv: cannot write: no process is reading it' -- \
    timeout 20 "$radiosity" solve "${small[@]}" --log pipe.csv >stdout
check "FIFO still a FIFO" test -p pipe.csv
mkfifo pipe.pfm
expect_exit 1 'pipe.pfm: cannot write: no process is reading it' -- \
    timeout 20 "$radiosity" render cornell --elements 50 --width 8 --height 8 --quiet -o pipe.pfm \
    --final-gather 0
check "image FIFO still a FIFO" test -p pipe.pfm

# A Unix socket with a listener gets the data (where python3 is there to listen).
if command -v python3 >/dev/null; then
    python3 - <<'PY' &
import os, socket
s = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
s.bind("sock.csv"); s.listen(1); s.settimeout(20)
open("listening", "w").close()
c, _ = s.accept(); data = b""
while True:
    chunk = c.recv(65536)
    if not chunk: break
    data += chunk
open("from-socket.csv", "wb").write(data)
PY
    listener=$!
    for _ in $(seq 100); do [[ -e listening ]] && break; sleep 0.05; done
    timeout 20 "$radiosity" solve "${small[@]}" --log sock.csv >stdout
    check "solve into a socket exits 0" test $? -eq 0
    wait "$listener"
    check "socket listener got the log" grep -q '^iteration,' from-socket.csv
    check "socket not replaced" test -S sock.csv
fi

# Devices made here (as root in a container this usually works; skipped where it does not).
if mknod null c 1 3 2>/dev/null && mknod full c 1 7 2>/dev/null; then
    before=$(kind null)
    "$radiosity" solve "${small[@]}" --log null --plot null >stdout
    check "solve into a null device exits 0" test $? -eq 0
    check "null device not replaced" test "$(kind null)" = "$before"
    ln -s null null.png
    "$radiosity" render cornell --elements 50 --width 8 --height 8 --final-gather 0 --quiet -o null.png
    check "image through a link to a device exits 0" test $? -eq 0
    check "null device still a device" test -c null
    expect_exit 1 'full: write failed: No space left on device' -- \
        "$radiosity" solve "${small[@]}" --log full
    check "full device not replaced" test -c full
    ln -s full full.ply
    expect_exit 1 'full.ply: write failed: No space left on device' -- \
        "$radiosity" bake unit-cube --elements 12 --quiet -o full.ply
    check "bake leaves the link to the device" test -L full.ply -a -c full
else
    echo "note: mknod not allowed here; the device checks are skipped"
fi

# A directory is refused before any work.
expect_exit 1 'sub: is a directory, not a file' -- "$radiosity" solve "${small[@]}" --log sub

# Hostile environments (issue 13): a read-only directory, two writers to one output, SIGKILL in
# the middle of a command, a full disk. Each: the documented exit status and line, the target
# whole (old or new, never partial), no temporary left (but after SIGKILL, where the writer
# cannot clean up and docs/errors.md allows a FILE.tmp-XXXXXX beside the target).
# A read-only directory: root writes anywhere, so as root the command runs as nobody.
mkdir ro && echo old >ro/kept.csv && chmod 555 ro
as_user=()
if [[ $(id -u) == 0 ]]; then
    if command -v setpriv >/dev/null; then
        as_user=(setpriv --reuid=65534 --regid=65534 --clear-groups)
        chmod 755 "$work"
    else
        as_user=(skip)
    fi
fi
if [[ ${as_user[0]-} == skip ]]; then
    echo "note: root without setpriv; the read-only directory checks are skipped"
else
    expect_exit 1 'ro/new.csv: cannot write: Permission denied' -- \
        "${as_user[@]}" "$radiosity" solve "${small[@]}" --log ro/new.csv
    expect_exit 1 'ro/kept.csv: cannot write: Permission denied' -- \
        "${as_user[@]}" "$radiosity" solve "${small[@]}" --log ro/kept.csv
    check "read-only directory: the old file kept, nothing added" \
        test "$(cat ro/kept.csv)" = old -a "$(ls -a ro | wc -l)" -eq 3
fi
chmod 755 ro

# Two writers to one output at once: the file ends up as one writer's whole output.
render_to() { "$radiosity" render cornell --width "$1" --height "$1" --elements 100 --threads 1 \
    --quiet -o "$2" >stdout 2>&1; }
render_to 32 one.pfm
render_to 48 two.pfm
for round in 1 2 3; do
    render_to 32 both.pfm &
    render_to 48 both.pfm &
    wait
    check "two writers (round $round): one whole output" \
        bash -c 'cmp -s both.pfm one.pfm || cmp -s both.pfm two.pfm'
done
check "two writers: no temporary left" test -z "$(ls -a | grep '\.tmp-')"

# SIGKILL at any moment of a render: the target is the old file or the whole new image.
"$radiosity" render cornell --width 256 --height 256 --elements 300 --threads 1 --quiet \
    -o whole.pfm >stdout
for delay in 0.05 0.2 0.5 1 2; do
    echo old >killed.pfm
    "$radiosity" render cornell --width 256 --height 256 --elements 300 --threads 1 --quiet \
        -o killed.pfm >stdout 2>&1 &
    sleep "$delay"
    kill -KILL $! 2>/dev/null
    wait $! 2>/dev/null
    check "SIGKILL after $delay s: old or whole" \
        bash -c '[[ $(cat killed.pfm) == old ]] || cmp -s killed.pfm whole.pfm'
    rm -f killed.pfm.tmp-* # allowed after SIGKILL (docs/errors.md, "Interrupting")
done

# A full disk: a 64 KiB tmpfs where this process may mount one (root), else skipped.
mkdir small
if mount -t tmpfs -o size=64k tmpfs small 2>/dev/null; then
    echo old >small/image.pfm
    expect_exit 1 'small/image.pfm: write failed: No space left on device' -- \
        "$radiosity" render cornell --width 128 --height 128 --elements 100 --threads 1 \
        --quiet -o small/image.pfm
    check "full disk: the old file kept" test "$(cat small/image.pfm)" = old
    check "full disk: no temporary left" test "$(ls -a small | wc -l)" -eq 3
    umount small
else
    echo "note: cannot mount a small tmpfs here (not root); the full-disk checks are skipped"
fi
rmdir small

finish
