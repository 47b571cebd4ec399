#!/usr/bin/env python3
"""isoterra - send one command to QEMU's human monitor (-monitor unix:SOCK)
and print its answer:  hmp.py SOCK 'screendump /path/x.ppm'"""
import socket
import sys


def read_prompt(s):
    buf = b""
    while not buf.endswith(b"(qemu) "):
        chunk = s.recv(4096)
        if not chunk:
            raise SystemExit("hmp: monitor closed the connection")
        buf += chunk
    return buf


def main():
    if len(sys.argv) != 3:
        raise SystemExit("usage: hmp.py SOCK COMMAND")
    s = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
    s.settimeout(60)
    s.connect(sys.argv[1])
    read_prompt(s)
    s.sendall(sys.argv[2].encode() + b"\n")
    out = read_prompt(s).decode(errors="replace")
    # the echo of the command, then its output, then the prompt
    lines = [l for l in out.replace("\r", "").split("\n")[1:-1] if l.strip()]
    if lines:
        print("\n".join(lines))
    s.close()


if __name__ == "__main__":
    main()
