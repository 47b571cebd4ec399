#!/usr/bin/env python3
"""isoterra VM tests: asks QEMU's VNC server (a unix socket) for a new
display size, as a VNC viewer whose window was resized would (RFB 3.8,
no authentication, SetDesktopSize of the ExtendedDesktopSize extension).
QEMU passes the size to the virtio-gpu device, which tells the guest's
driver: the connector's preferred mode becomes that size and the kernel
sends a hotplug event.  This is how a test changes the monitor's preferred
mode while a program drives it.

    vnc_resize.py SOCKET WIDTH HEIGHT

Prints the server's answer; exit 0 when it took the request."""
import socket
import struct
import sys

EXT_DESKTOP_SIZE = -308  # pseudo-encoding: the client can ask for sizes
SET_DESKTOP_SIZE = 251   # client message
STATUS = {0: "no error", 1: "resize is administratively prohibited", 2: "out of resources",
          3: "invalid screen layout", 4: "request forwarded (might complete asynchronously)"}


def recv_exact(s, n):
    b = b""
    while len(b) < n:
        c = s.recv(n - len(b))
        if not c:
            raise EOFError("the VNC server closed the connection")
        b += c
    return b


def main():
    if len(sys.argv) != 4:
        sys.exit("usage: vnc_resize.py SOCKET WIDTH HEIGHT")
    path, w, h = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
    s = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
    s.settimeout(20)
    s.connect(path)
    version = recv_exact(s, 12)
    if not version.startswith(b"RFB 003."):
        sys.exit("not an RFB server: %r" % version)
    s.sendall(b"RFB 003.008\n")
    (ntypes,) = struct.unpack("B", recv_exact(s, 1))
    if ntypes == 0:
        (n,) = struct.unpack(">I", recv_exact(s, 4))
        sys.exit("the server refused: %s" % recv_exact(s, n).decode(errors="replace"))
    types = recv_exact(s, ntypes)
    if 1 not in types:
        sys.exit("the server wants authentication (security types %s)" % list(types))
    s.sendall(b"\x01")
    (result,) = struct.unpack(">I", recv_exact(s, 4))
    if result != 0:
        sys.exit("security handshake failed (%d)" % result)
    s.sendall(b"\x01")  # ClientInit: shared
    sw, sh = struct.unpack(">HH", recv_exact(s, 4))
    recv_exact(s, 16)  # pixel format
    (nlen,) = struct.unpack(">I", recv_exact(s, 4))
    name = recv_exact(s, nlen).decode(errors="replace")
    print("vnc: '%s' is %dx%d; asking for %dx%d" % (name, sw, sh, w, h))
    # SetEncodings: raw, and the extended desktop size pseudo-encoding
    s.sendall(struct.pack(">BxHii", 2, 2, 0, EXT_DESKTOP_SIZE))
    # SetDesktopSize: one screen covering the whole desktop
    s.sendall(struct.pack(">BxHHBx", SET_DESKTOP_SIZE, w, h, 1) + struct.pack(">IHHHHI", 0, 0, 0, w, h, 0))
    # the answer: a FramebufferUpdate holding an ExtendedDesktopSize
    # rectangle whose x is the reason (1: this client asked) and y the status
    while True:
        mtype = recv_exact(s, 1)[0]
        if mtype == 0:  # FramebufferUpdate
            (nrects,) = struct.unpack(">xH", recv_exact(s, 3))
            for _ in range(nrects):
                x, y, rw, rh, enc = struct.unpack(">HHHHi", recv_exact(s, 12))
                if enc == EXT_DESKTOP_SIZE:
                    (nscreens,) = struct.unpack(">B3x", recv_exact(s, 4))
                    recv_exact(s, 16 * nscreens)
                    if x == 1:
                        print("vnc: answer %d (%s), desktop %dx%d" % (y, STATUS.get(y, "?"), rw, rh))
                        sys.exit(0 if y in (0, 4) else 1)
                else:
                    sys.exit("vnc: unexpected rectangle encoding %d before the answer" % enc)
        elif mtype == 2:  # Bell
            continue
        else:
            sys.exit("vnc: unexpected server message %d before the answer" % mtype)


if __name__ == "__main__":
    main()
