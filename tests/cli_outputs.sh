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

finish
