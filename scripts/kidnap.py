#!/usr/bin/env python3
"""Makes a kidnapped copy of a TUM-layout sequence for relocalisation tests, without
copying its images: the lists of the copy point at the original files.
  scripts/kidnap.py SRC OUT --drop A B    frames A..B (0-based, inclusive) removed:
                                          the camera jumps
  scripts/kidnap.py SRC OUT --black A B   frames A..B replaced by black images with
                                          zero depth (written into OUT)
Frames are the lines of SRC's associations.txt (else of rgb.txt and depth.txt paired
by line). groundtruth.txt and sgslam.yaml are linked."""
import argparse
import os
import struct
import sys
import zlib


def data_lines(path):
    with open(path, encoding="utf-8") as f:
        return [l.split() for l in f if l.strip() and not l.startswith("#")]


def png(width, height, bit_depth, colour_type, channels):
    """A black PNG (8-bit grey/RGB or 16-bit grey)."""
    row = b"\x00" + bytes(width * channels * bit_depth // 8)
    raw = zlib.compress(row * height, 9)
    def chunk(kind, body):
        return struct.pack(">I", len(body)) + kind + body + struct.pack(">I", zlib.crc32(kind + body) & 0xFFFFFFFF)
    header = struct.pack(">IIBBBBB", width, height, bit_depth, colour_type, 0, 0, 0)
    return b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header) + chunk(b"IDAT", raw) + chunk(b"IEND", b"")


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("src")
    p.add_argument("out")
    g = p.add_mutually_exclusive_group(required=True)
    g.add_argument("--drop", nargs=2, type=int, metavar=("A", "B"))
    g.add_argument("--black", nargs=2, type=int, metavar=("A", "B"))
    p.add_argument("--size", nargs=2, type=int, default=(640, 480), metavar=("W", "H"))
    a = p.parse_args()
    src = os.path.abspath(a.src)
    if os.path.exists(os.path.join(src, "associations.txt")):
        frames = [(l[0], l[1], l[2], l[3]) for l in data_lines(os.path.join(src, "associations.txt"))]
    else:
        rgb, depth = data_lines(os.path.join(src, "rgb.txt")), data_lines(os.path.join(src, "depth.txt"))
        frames = [(r[0], r[1], d[0], d[1]) for r, d in zip(rgb, depth)]
    first, last = a.drop or a.black
    if not 0 <= first <= last < len(frames):
        sys.exit(f"error: frames {first}..{last} are not within the sequence's 0..{len(frames) - 1}")
    os.makedirs(a.out, exist_ok=True)
    if a.black:
        os.makedirs(os.path.join(a.out, "black"), exist_ok=True)
        w, h = a.size
        with open(os.path.join(a.out, "black", "rgb.png"), "wb") as f:
            f.write(png(w, h, 8, 2, 3))
        with open(os.path.join(a.out, "black", "depth.png"), "wb") as f:
            f.write(png(w, h, 16, 0, 1))
    lines = []
    for i, (t_rgb, rgb, t_depth, depth) in enumerate(frames):
        if first <= i <= last:
            if a.drop:
                continue
            rgb, depth = os.path.join("black", "rgb.png"), os.path.join("black", "depth.png")
        else:
            rgb, depth = os.path.join(src, rgb), os.path.join(src, depth)
        lines.append((t_rgb, rgb, t_depth, depth))
    with open(os.path.join(a.out, "associations.txt"), "w", encoding="utf-8") as f:
        f.writelines(f"{r} {rp} {d} {dp}\n" for r, rp, d, dp in lines)
    with open(os.path.join(a.out, "rgb.txt"), "w", encoding="utf-8") as f:
        f.writelines(f"{r} {rp}\n" for r, rp, _, _ in lines)
    with open(os.path.join(a.out, "depth.txt"), "w", encoding="utf-8") as f:
        f.writelines(f"{d} {dp}\n" for _, _, d, dp in lines)
    for name in ("groundtruth.txt", "sgslam.yaml"):
        target, link = os.path.join(src, name), os.path.join(a.out, name)
        if os.path.exists(target) and not os.path.lexists(link):
            os.symlink(target, link)
    print(f"{a.out}: {len(lines)} of {len(frames)} frames ({'dropped' if a.drop else 'black'} {first}..{last})")


if __name__ == "__main__":
    main()
