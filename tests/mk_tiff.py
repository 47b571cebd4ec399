#!/usr/bin/env python3
# isoterra — a small GeoTIFF-readable test file: a 32x32 16-bit grayscale
# baseline TIFF (one strip, uncompressed) holding a round hill.  Used by
# tools/debpkg.sh: the installed isoterra-geotiff reads it through GDAL.
#   python3 tests/mk_tiff.py OUT.tif
import struct, sys, math
W = H = 32
pix = b''.join(struct.pack('<H', int(20000 + 30000 * math.exp(-((x - 16) ** 2 + (y - 16) ** 2) / 60.0)))
               for y in range(H) for x in range(W))
tags = [(256, 3, 1, W), (257, 3, 1, H), (258, 3, 1, 16), (259, 3, 1, 1), (262, 3, 1, 1),
        (273, 4, 1, 0), (277, 3, 1, 1), (278, 3, 1, H), (279, 4, 1, len(pix)), (339, 3, 1, 1)]
ifd_off = 8
data_off = ifd_off + 2 + 12 * len(tags) + 4
out = b'II*\0' + struct.pack('<I', ifd_off) + struct.pack('<H', len(tags))
for tag, typ, n, v in tags:
    if tag == 273:
        v = data_off
    out += struct.pack('<HHI', tag, typ, n) + (struct.pack('<HH', v, 0) if typ == 3 else struct.pack('<I', v))
out += struct.pack('<I', 0) + pix
open(sys.argv[1], 'wb').write(out)
