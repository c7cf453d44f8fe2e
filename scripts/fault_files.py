"""Files for scripts/faults.py: the damaged inputs it plants (PNG, JPEG, lists) and
the checks that an output of `sgslam run` is complete (each returns a problem, or
None when the file is whole). Python 3 standard library only."""
import json
import math
import os
import struct
import zlib

PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"


# --- inputs ---------------------------------------------------------------

def png_chunk(kind, body):
    return struct.pack(">I", len(body)) + kind + body + struct.pack(">I", zlib.crc32(kind + body) & 0xFFFFFFFF)


def png_header(width, height, bit_depth, colour_type):
    return png_chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, bit_depth, colour_type, 0, 0, 0))


def png_bytes(width, height, bit_depth=8, colour_type=2, value=0):
    """A flat PNG: colour_type 0 grey, 2 RGB; every sample `value`."""
    channels = 3 if colour_type == 2 else 1
    sample = value.to_bytes(bit_depth // 8, "big")
    row = b"\x00" + sample * (width * channels)
    return PNG_SIGNATURE + png_header(width, height, bit_depth, colour_type) + \
        png_chunk(b"IDAT", zlib.compress(row * height, 9)) + png_chunk(b"IEND", b"")


def png_claiming(width, height):
    """A PNG of a few hundred bytes whose header claims width x height RGB pixels:
    its data holds one row, then the file ends."""
    row = b"\x00" + bytes(min(width, 4096) * 3)
    return PNG_SIGNATURE + png_header(width, height, 8, 2) + png_chunk(b"IDAT", zlib.compress(row, 9)) + \
        png_chunk(b"IEND", b"")


def png_zeros_streamed(path, width, height):
    """A true black RGB PNG of width x height written row by row: about 1 MB on disk
    for 20000 x 15000 pixels (900 MB decoded)."""
    row = b"\x00" * (1 + 3 * width)
    z = zlib.compressobj(9)
    with open(path, "wb") as f:
        f.write(PNG_SIGNATURE + png_header(width, height, 8, 2))
        data = bytearray()
        for _ in range(height):
            data += z.compress(row)
        data += z.flush()
        f.write(png_chunk(b"IDAT", bytes(data)))
        f.write(png_chunk(b"IEND", b""))


def jpeg_grey(width, height):
    """A baseline greyscale JPEG, mid grey: one Huffman code of one bit for the DC
    difference 0 and one for end-of-block, so each 8x8 block is two zero bits."""
    def segment(marker, body):
        return b"\xff" + bytes([marker]) + struct.pack(">H", len(body) + 2) + body
    dqt = segment(0xDB, b"\x00" + bytes([1] * 64))
    sof = segment(0xC0, struct.pack(">BHHB", 8, height, width, 1) + b"\x01\x11\x00")
    one_code = bytes([1] + [0] * 15) + b"\x00"
    dht = segment(0xC4, b"\x00" + one_code + b"\x10" + one_code)
    sos = segment(0xDA, b"\x01\x01\x00\x00\x3f\x00")
    blocks = ((width + 7) // 8) * ((height + 7) // 8)
    scan = bytes((2 * blocks + 7) // 8)
    return b"\xff\xd8" + dqt + sof + dht + sos + scan + b"\xff\xd9"


def png_read(path):
    """(width, height, bit_depth, colour_type, samples) of a non-interlaced PNG, the
    samples a flat list of ints, rows unfiltered."""
    with open(path, "rb") as f:
        data = f.read()
    if not data.startswith(PNG_SIGNATURE):
        raise ValueError(f"{path}: not a PNG")
    pos, idat, header = 8, bytearray(), None
    while pos < len(data):
        (length,) = struct.unpack(">I", data[pos:pos + 4])
        kind, body = data[pos + 4:pos + 8], data[pos + 8:pos + 8 + length]
        if kind == b"IHDR":
            header = struct.unpack(">IIBBBBB", body)
        elif kind == b"IDAT":
            idat += body
        pos += 12 + length
    width, height, bit_depth, colour_type = header[:4]
    channels = {0: 1, 2: 3, 4: 2, 6: 4}[colour_type]
    bpp = channels * bit_depth // 8
    raw = zlib.decompress(bytes(idat))
    stride = width * bpp
    rows, prev = [], bytearray(stride)
    for y in range(height):
        kind = raw[y * (stride + 1)]
        line = bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        unfilter(kind, line, prev, bpp)
        rows.append(line)
        prev = line
    flat = b"".join(rows)
    if bit_depth == 16:
        samples = list(struct.unpack(f">{len(flat) // 2}H", flat))
    else:
        samples = list(flat)
    return width, height, bit_depth, colour_type, samples


def unfilter(kind, line, prev, bpp):
    n = len(line)
    if kind == 1:
        for i in range(bpp, n):
            line[i] = (line[i] + line[i - bpp]) & 0xFF
    elif kind == 2:
        for i in range(n):
            line[i] = (line[i] + prev[i]) & 0xFF
    elif kind == 3:
        for i in range(n):
            left = line[i - bpp] if i >= bpp else 0
            line[i] = (line[i] + ((left + prev[i]) >> 1)) & 0xFF
    elif kind == 4:
        for i in range(n):
            a = line[i - bpp] if i >= bpp else 0
            b = prev[i]
            c = prev[i - bpp] if i >= bpp else 0
            p = a + b - c
            pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
            line[i] = (line[i] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 0xFF


def png16_write(path, width, height, samples):
    raw = bytearray()
    for y in range(height):
        raw += b"\x00" + struct.pack(f">{width}H", *samples[y * width:(y + 1) * width])
    with open(path, "wb") as f:
        f.write(PNG_SIGNATURE + png_header(width, height, 16, 0) + png_chunk(b"IDAT", zlib.compress(bytes(raw), 6)) +
                png_chunk(b"IEND", b""))


# --- outputs --------------------------------------------------------------

def data_lines(path):
    with open(path, encoding="utf-8", errors="replace") as f:
        return [l for l in f.read().splitlines() if l.strip() and not l.startswith("#")]


def check_text_complete(path):
    with open(path, "rb") as f:
        data = f.read()
    if data and not data.endswith(b"\n"):
        return "does not end with a newline (cut short?)"
    return None


def check_tum(path):
    """A TUM trajectory: 8 finite numbers a line, quaternions of unit norm."""
    problem = check_text_complete(path)
    if problem:
        return problem
    for n, line in enumerate(data_lines(path), 1):
        fields = line.split()
        try:
            values = [float(v) for v in fields]
        except ValueError:
            return f"line {n}: not numbers"
        if len(values) != 8 or not all(math.isfinite(v) for v in values):
            return f"line {n}: expected 8 finite numbers"
        if abs(math.sqrt(sum(q * q for q in values[4:])) - 1) > 1e-3:
            return f"line {n}: quaternion not of unit norm"
    return None


def check_csv(path):
    problem = check_text_complete(path)
    if problem:
        return problem
    with open(path, encoding="utf-8") as f:
        rows = [r.split(",") for r in f.read().splitlines()]
    if not rows:
        return "empty"
    widths = {len(r) for r in rows}
    return None if len(widths) == 1 else f"rows of {sorted(widths)} columns"


def check_json(path):
    try:
        with open(path, encoding="utf-8") as f:
            json.load(f)
    except (ValueError, UnicodeDecodeError) as e:
        return f"not valid JSON: {e}"
    return None


PLY_SIZES = {"char": 1, "uchar": 1, "short": 2, "ushort": 2, "int": 4, "uint": 4, "float": 4, "double": 8,
             "int8": 1, "uint8": 1, "int16": 2, "uint16": 2, "int32": 4, "uint32": 4, "float32": 4, "float64": 8}


def ply_vertices(path):
    """The vertex count of a PLY file, or raise ValueError when the file does not
    hold exactly what its header says."""
    with open(path, "rb") as f:
        data = f.read()
    end = data.find(b"end_header\n")
    if not data.startswith(b"ply\n") or end < 0:
        raise ValueError("no PLY header")
    header = data[:end].decode("ascii", "replace").splitlines()
    body = data[end + len("end_header\n"):]
    fmt = next((l.split()[1] for l in header if l.startswith("format ")), "")
    count, record = 0, 0
    for line in header:
        words = line.split()
        if words[:2] == ["element", "vertex"]:
            count = int(words[2])
        elif words[:1] == ["element"]:
            raise ValueError(f"unexpected element {words[1]}")
        elif words[:1] == ["property"]:
            record += PLY_SIZES[words[1]]
    if fmt.startswith("binary"):
        if len(body) != count * record:
            raise ValueError(f"header says {count} vertices ({count * record} bytes), body has {len(body)} bytes")
    elif fmt == "ascii":
        if len(body.decode("ascii", "replace").splitlines()) != count:
            raise ValueError(f"header says {count} vertices, body has another number of lines")
    else:
        raise ValueError(f"unknown format {fmt!r}")
    return count


def check_ply(path):
    try:
        ply_vertices(path)
    except (ValueError, KeyError, IndexError) as e:
        return str(e)
    return None


def check_png(path):
    with open(path, "rb") as f:
        data = f.read()
    if not data.startswith(PNG_SIGNATURE) or not data.endswith(png_chunk(b"IEND", b"")):
        return "not a whole PNG (signature or IEND missing)"
    return None


def check_octomap(path):
    """A binary OctoMap (.bt: each inner node two bytes, two bits a child, 11 for a
    child with children, written depth first): the tree must end with the file and
    hold as many nodes as the header says."""
    with open(path, "rb") as f:
        data = f.read()
    end = data.find(b"\ndata\n")
    if not data.startswith(b"# Octomap OcTree binary file") or end < 0:
        return "no binary OctoMap header"
    header = dict(l.split(" ", 1) for l in data[:end].decode("ascii", "replace").splitlines()
                  if l and not l.startswith("#") and " " in l)
    pos, pending, nodes = end + len("\ndata\n"), 1, 1
    if header.get("size", "").strip() == "0" and pos == len(data):
        return None  # an empty tree: no node at all
    while pending:
        if pos + 2 > len(data):
            return f"node tree cut short after {nodes} nodes"
        pairs = [(data[pos + i // 4] >> (2 * (i % 4))) & 3 for i in range(8)]
        pending += pairs.count(3) - 1
        nodes += sum(1 for p in pairs if p)
        pos += 2
    if pos != len(data):
        return f"{len(data) - pos} bytes after the node tree"
    if int(header.get("size", -1)) != nodes:
        return f"header says {header.get('size')} nodes, the tree has {nodes}"
    return None


CHECKERS = {
    "trajectory.txt": check_tum, "trajectory_online.txt": check_tum, "keyframes.txt": check_tum,
    "frames.csv": check_csv, "stats.json": check_json, "objects.json": check_json,
    "map_points.ply": check_ply, "cloud.ply": check_ply, "map_top.png": check_png,
    "octomap.bt": check_octomap, "config_used.yaml": check_text_complete, "detections.txt": check_text_complete,
    "cloud_live.ply": check_ply, "octomap_live.bt": check_octomap,
}


def check_output_file(path):
    """A problem with the output file at path, or None (unknown names: None)."""
    checker = CHECKERS.get(os.path.basename(path))
    if checker is None or not os.path.isfile(path):
        return None
    try:
        return checker(path)
    except OSError as e:
        return f"unreadable: {e}"
