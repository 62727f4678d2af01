#!/usr/bin/env python3
"""Run a command on a pseudo-terminal (its standard input, output and
error), as a user at a terminal would, and write all it printed to the
file named first, byte for byte; exit with the command's status.

    python3 tests/tools/pty_run.py OUT COMMAND [ARGS...]
"""
import os
import pty
import sys


def main():
    out, argv = sys.argv[1], sys.argv[2:]
    pid, fd = pty.fork()
    if pid == 0:
        os.execvp(argv[0], argv)
    got = b""
    while True:
        try:
            data = os.read(fd, 65536)
        except OSError:   # EIO: the command closed the terminal
            break
        if not data:
            break
        got += data
    _, status = os.waitpid(pid, 0)
    with open(out, "wb") as f:
        f.write(got)
    sys.exit(os.waitstatus_to_exitcode(status))


main()
