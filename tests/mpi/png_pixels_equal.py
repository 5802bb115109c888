"""png_pixels_equal.py A.png B.png: exit 0 when the two PNGs (8-bit, non-interlaced, RGB or
RGBA) have the same size and pixels, decoded with the standard library alone (zlib + the PNG
row filters), so that another zlib or filter choice does not matter; else 1 with a reason."""
import struct
import sys
import zlib


def pixels(path):
    with open(path, "rb") as f:
        data = f.read()
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        raise ValueError(f"{path}: not a PNG")
    pos, idat, header = 8, b"", None
    while pos < len(data):
        n, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + n]
        if kind == b"IHDR":
            header = struct.unpack(">IIBBBBB", body)
        elif kind == b"IDAT":
            idat += body
        pos += 12 + n
    width, height, depth, colour, _, _, interlace = header
    if depth != 8 or colour not in (2, 6) or interlace != 0:
        raise ValueError(f"{path}: only 8-bit non-interlaced RGB/RGBA is read here")
    bpp = 3 if colour == 2 else 4
    raw, stride = zlib.decompress(idat), width * bpp
    rows, prev = [], bytearray(stride)
    for y in range(height):
        kind, line = raw[y * (stride + 1)], bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        for x in range(stride):
            a = line[x - bpp] if x >= bpp else 0
            b, c = prev[x], prev[x - bpp] if x >= bpp else 0
            if kind == 1:
                line[x] = (line[x] + a) & 255
            elif kind == 2:
                line[x] = (line[x] + b) & 255
            elif kind == 3:
                line[x] = (line[x] + (a + b) // 2) & 255
            elif kind == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                line[x] = (line[x] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        rows.append(bytes(line))
        prev = line
    return (width, height, bpp), b"".join(rows)


(shape_a, a), (shape_b, b) = pixels(sys.argv[1]), pixels(sys.argv[2])
if shape_a != shape_b:
    sys.exit(f"{sys.argv[1]} is {shape_a}, {sys.argv[2]} is {shape_b}")
if a != b:
    differ = sum(1 for x, y in zip(a, b) if x != y)
    sys.exit(f"{sys.argv[1]} and {sys.argv[2]}: {differ} of {len(a)} bytes of pixels differ")
