#!/usr/bin/python3
"""Reference for gather's map loader: a port of ROS 1 map_server.

ROS 1 map_server is not packaged in Debian 12, so this script ports, line by
line, what map_server does with a map image and writes the results as test
fixtures for tests/core/map_loader_test.cpp (the C++ test does not need Python):

  tests/core/fixtures/map_server/<image>            the image (PGM or PNG)
  tests/core/fixtures/map_server/<case>.yaml        map_server YAML
  tests/core/fixtures/map_server/<case>.expected    expected grid
  tests/core/fixtures/map_server/cases.txt          one case name a line

<case>.expected (text):
  line 1: width height
  line 2: resolution origin_x origin_y
  then `height` lines of `width` int8 values (nav_msgs/OccupancyGrid data),
  map order: first line = map row 0 = bottom row of the image;
  then `height` lines of `width` 0/1 = gather's free mask (same row order):
  free = value 0 in trinary/scale; raw: 0 <= value <= 100 and value/100 < free_thresh.

Two parts:
  1. sdl_surface(): what SDL_image 1.2 (IMG_Load, the loader map_server uses:
     map_server/package.xml depends on sdl + sdl-image) hands map_server for
     each PNG / PGM flavour: bytes per pixel and whether the surface has an
     alpha mask (SDL's Amask). It is computed from the raw samples the fixture
     was generated from - not from a decoder - so it checks our decoder too.
  2. load_map_from_file(): map_server/src/image_loader.cpp loadMapFromFile()
     (ros-planning/navigation, noetic), the thresholding loop.

The images are written by a minimal PNG/PGM encoder here (so every bit depth,
colour type, PLTE and tRNS combination is under control), and PIL reads every
PNG back as an independent check of that encoder.

Run: /usr/bin/python3 tests/core/map_server_reference.py   (rewrites the fixtures)
"""
import os
import struct
import sys
import zlib

import numpy as np
from PIL import Image

HERE = os.path.dirname(os.path.abspath(__file__))
OUT = os.path.join(HERE, "fixtures", "map_server")

W, H = 7, 5  # small fixtures, image row 0 = top

# --------------------------------------------------------------------------
# Raw sample data (image order, row 0 = top). Spread over every threshold
# region, with exact-threshold values (102 -> occ 0.6, 204 -> occ 0.2) and
# values around the default thresholds (89/90 and 205/206).
GRAY = np.array([
    0, 1, 10, 50, 88, 89, 90,
    91, 100, 101, 102, 127, 128, 129,
    150, 154, 155, 156, 180, 200, 203,
    204, 205, 206, 207, 230, 250, 254,
    255, 255, 0, 64, 192, 32, 224,
], dtype=np.int64).reshape(H, W)

# Alpha spread: transparent, almost transparent, translucent, opaque.
_ALPHAS = [255, 0, 1, 128, 254, 255, 60, 200]
ALPHA = np.array([_ALPHAS[(3 * i) % 8] for i in range(W * H)], dtype=np.int64).reshape(H, W)

_flat = GRAY.flatten()
RED = np.array([_flat[(i * 11) % 35] for i in range(35)], dtype=np.int64).reshape(H, W)
GREEN = np.array([_flat[(i * 17 + 3) % 35] for i in range(35)], dtype=np.int64).reshape(H, W)
BLUE = np.array([_flat[(i * 23 + 5) % 35] for i in range(35)], dtype=np.int64).reshape(H, W)


# --------------------------------------------------------------------------
# Minimal encoders.

def _chunk(tag, data):
    return struct.pack(">I", len(data)) + tag + data + struct.pack(">I", zlib.crc32(tag + data) & 0xFFFFFFFF)


def png_bytes(samples, bit_depth, color_type, plte=None, trns=None):
    """samples: (H, W, C) ints in the file's sample range. Filter 0 on every row."""
    h, w, c = samples.shape
    raw = bytearray()
    for r in range(h):
        raw.append(0)
        row = samples[r].reshape(-1)
        if bit_depth == 16:
            for v in row:
                raw += struct.pack(">H", int(v))
        elif bit_depth == 8:
            raw += bytes(int(v) for v in row)
        else:  # 1, 2, 4: packed MSB first, rows padded to a byte
            per = 8 // bit_depth
            for k in range(0, len(row), per):
                byte = 0
                for j in range(per):
                    v = int(row[k + j]) if k + j < len(row) else 0
                    byte |= v << (8 - bit_depth * (j + 1))
                raw.append(byte)
    out = b"\x89PNG\r\n\x1a\n"
    out += _chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, bit_depth, color_type, 0, 0, 0))
    if plte is not None:
        out += _chunk(b"PLTE", bytes(v for rgb in plte for v in rgb))
    if trns is not None:
        out += _chunk(b"tRNS", trns)
    out += _chunk(b"IDAT", zlib.compress(bytes(raw), 9))
    out += _chunk(b"IEND", b"")
    return out


def pgm_bytes(samples, maxval, ascii_):
    h, w = samples.shape
    if ascii_:
        lines = ["P2", "# gather map_server fixture", "%d %d" % (w, h), str(maxval)]
        lines += [" ".join(str(int(v)) for v in row) for row in samples]
        return ("\n".join(lines) + "\n").encode()
    return b"P5\n# gather map_server fixture\n%d %d\n%d\n" % (w, h, maxval) + bytes(int(v) for v in samples.flatten())


# --------------------------------------------------------------------------
# Part 1: what SDL_image 1.2 gives map_server (IMG_png.c / IMG_pnm.c).
# Returns (pixels (H, W, n) uint8, has_amask).

def sdl_surface(spec):
    kind = spec["kind"]
    s = spec["samples"]
    if kind == "pgm":
        # IMG_pnm.c: 8-bit palettized surface holding the gray level; if
        # maxval < 255: "scale up to full dynamic range": row[i] * 255 / maxval
        # (integer arithmetic).
        m = spec["maxval"]
        v = s[:, :, 0] * 255 // m if m < 255 else s[:, :, 0]
        return v[:, :, None].astype(np.uint8), False
    ct, bd = spec["color_type"], spec["bit_depth"]
    trns = spec.get("trns")
    if ct == 0:  # gray
        # IMG_png.c: png_set_strip_16 (16-bit -> high byte), png_set_packing,
        # and png_set_expand for gray ("scale greyscale values to the range
        # 0..255": 1/2/4-bit v -> v * 255 / (2^bd - 1)).
        g = s[:, :, 0]
        if bd == 16:
            g = g >> 8
        elif bd < 8:
            g = g * (255 // ((1 << bd) - 1))
        if trns is not None:
            # png_set_expand also sets PNG_EXPAND_tRNS: a gray image with a tRNS
            # colour becomes gray+alpha (2 bytes a pixel). SDL_image then sets
            # masks only for 4 channels (Amask = num_channels == 4 ? ... : 0), so
            # map_server sees 2 channels without Amask: it averages gray AND
            # alpha, and takes alpha from the last byte.
            key = struct.unpack(">H", trns)[0]
            a = np.where(s[:, :, 0] == key, 0, 255)
            return np.stack([g, a], axis=2).astype(np.uint8), False
        return g[:, :, None].astype(np.uint8), False
    if ct == 4:  # gray + alpha -> png_set_gray_to_rgb -> RGBA, Amask set
        g, a = s[:, :, 0], s[:, :, 1]
        if bd == 16:
            g, a = g >> 8, a >> 8
        return np.stack([g, g, g, a], axis=2).astype(np.uint8), True
    if ct == 2:  # RGB: 3 bytes, no Amask (a tRNS colour is only a colour key)
        v = s >> 8 if bd == 16 else s
        return v.astype(np.uint8), False
    if ct == 6:  # RGBA: 4 bytes, Amask set
        v = s >> 8 if bd == 16 else s
        return v.astype(np.uint8), True
    if ct == 3:  # palette
        idx = s[:, :, 0]
        if trns is not None:
            # "Check if all tRNS entries are opaque except one": the surface stays
            # a palette surface (colour key) unless an entry is translucent or more
            # than one entry is fully transparent; then png_set_expand -> RGBA and,
            # since SDL_image re-reads the colour type after png_read_update_info,
            # Amask is set.
            t = list(trns)
            zeros = sum(1 for v in t if v == 0)
            partial = any(v not in (0, 255) for v in t)
            if zeros > 1 or partial:
                plte = spec["plte"]
                rgba = np.zeros((H, W, 4), dtype=np.int64)
                for r in range(idx.shape[0]):
                    for c in range(idx.shape[1]):
                        i = int(idx[r, c])
                        rgba[r, c, :3] = plte[i]
                        rgba[r, c, 3] = t[i] if i < len(t) else 255
                return rgba.astype(np.uint8), True
        # 8-bit palette surface: the pixel byte is the palette INDEX; map_server
        # never looks at the palette colours.
        return idx[:, :, None].astype(np.uint8), False
    raise ValueError(kind)


# --------------------------------------------------------------------------
# Part 2: map_server image_loader.cpp loadMapFromFile(), the pixel loop.
TRINARY, SCALE, RAW = "trinary", "scale", "raw"


def load_map_from_file(pixels, has_amask, negate, occ_th, free_th, mode):
    height, width, n_channels = pixels.shape  # n_channels = img->format->BytesPerPixel
    # "NOTE: Trinary mode still overrides here to preserve existing behavior.
    #  Alpha will be averaged in with color channels when using trinary mode."
    if mode == TRINARY or not has_amask:
        avg_channels = n_channels
    else:
        avg_channels = n_channels - 1
    data = [0] * (width * height)
    for j in range(height):
        for i in range(width):
            p = pixels[j, i]
            color_sum = 0
            for k in range(avg_channels):
                color_sum += int(p[k])
            color_avg = color_sum / float(avg_channels)
            if n_channels == 1:
                alpha = 1
            else:
                alpha = int(p[n_channels - 1])  # last byte: blue for RGB (quirk kept)
            if negate:
                color_avg = 255 - color_avg
            idx = width * (height - j - 1) + i  # MAP_IDX(width, i, height - j - 1)
            if mode == RAW:
                value = int(color_avg)  # unsigned char value = color_avg (truncation)
                data[idx] = value - 256 if value > 127 else value  # stored in int8 data
                continue
            occ = (255 - color_avg) / 255.0
            if occ > occ_th:
                value = 100
            elif occ < free_th:
                value = 0
            elif mode == TRINARY or alpha < 1.0:
                value = -1
            else:
                ratio = (occ - free_th) / (occ_th - free_th)
                value = int(1 + 98 * ratio)  # double -> unsigned char truncation
            data[idx] = value
    return data


def free_mask(data, mode, free_th):
    if mode == RAW:
        return [1 if 0 <= v <= 100 and v / 100.0 < free_th else 0 for v in data]
    return [1 if v == 0 else 0 for v in data]


# --------------------------------------------------------------------------
# The fixtures.

def s3(*planes):
    return np.stack(planes, axis=2).astype(np.int64)


COLOR_PLTE = [((i * 37) % 256, (i * 91 + 13) % 256, 255 - i) for i in range(256)]
GRAY_PLTE = [(i, i, i) for i in range(256)]
PLTE16 = [((i * 53) % 256, (i * 29 + 100) % 256, (i * 71 + 7) % 256) for i in range(16)]
IDX16 = np.array([(i * 7) % 16 for i in range(35)], dtype=np.int64).reshape(H, W)

# Each image: spec + list of (mode or None for "no mode key", negate, occupied_thresh, free_thresh).
D = (0.65, 0.196)  # map_server's usual thresholds
E = (0.6, 0.2)     # exact-threshold pixels (102, 204) land on these
IMAGES = [
    ("p2.pgm", dict(kind="pgm", ascii=True, maxval=255, samples=GRAY[:, :, None]),
     [(TRINARY, 0) + D, (SCALE, 1) + D, (RAW, 0) + D]),
    ("p5.pgm", dict(kind="pgm", ascii=False, maxval=255, samples=GRAY[:, :, None]),
     [(None, 0) + D, (TRINARY, 1) + D, (TRINARY, 0) + E, (SCALE, 0) + D, (SCALE, 0) + E, (RAW, 0) + D, (RAW, 1) + D]),
    ("p5_max100.pgm", dict(kind="pgm", ascii=False, maxval=100, samples=(GRAY * 100 // 255)[:, :, None]),
     [(TRINARY, 0) + D, (SCALE, 1) + D, (RAW, 0) + D]),
    ("p2_max15.pgm", dict(kind="pgm", ascii=True, maxval=15, samples=(GRAY * 15 // 255)[:, :, None]),
     [(TRINARY, 1) + D, (SCALE, 0) + D, (RAW, 1) + D]),
    ("gray8.png", dict(kind="png", color_type=0, bit_depth=8, samples=GRAY[:, :, None]),
     [(TRINARY, 0) + D, (TRINARY, 1) + D, (SCALE, 0) + D, (SCALE, 1) + E, (RAW, 0) + D, (RAW, 1) + D]),
    ("gray16.png", dict(kind="png", color_type=0, bit_depth=16,
                        samples=(GRAY * 256 + (np.arange(35).reshape(H, W) * 37) % 256)[:, :, None]),
     [(TRINARY, 0) + D, (SCALE, 1) + D, (RAW, 0) + D]),
    ("gray1.png", dict(kind="png", color_type=0, bit_depth=1, samples=(GRAY >= 128).astype(np.int64)[:, :, None]),
     [(TRINARY, 0) + D, (SCALE, 1) + D, (RAW, 1) + D]),
    ("gray2.png", dict(kind="png", color_type=0, bit_depth=2, samples=(GRAY >> 6)[:, :, None]),
     [(TRINARY, 0) + D, (SCALE, 0) + D]),
    ("gray4.png", dict(kind="png", color_type=0, bit_depth=4, samples=(GRAY >> 4)[:, :, None]),
     [(TRINARY, 1) + D, (SCALE, 0) + D, (RAW, 0) + D]),
    ("gray8_trns.png", dict(kind="png", color_type=0, bit_depth=8, samples=GRAY[:, :, None], trns=struct.pack(">H", 255)),
     [(TRINARY, 0) + D, (SCALE, 0) + D, (RAW, 1) + D]),
    ("gray_alpha.png", dict(kind="png", color_type=4, bit_depth=8, samples=s3(GRAY, ALPHA)),
     [(TRINARY, 0) + D, (TRINARY, 1) + D, (SCALE, 0) + D, (SCALE, 1) + D, (RAW, 0) + D, (RAW, 1) + D]),
    ("rgb.png", dict(kind="png", color_type=2, bit_depth=8, samples=s3(RED, GREEN, BLUE)),
     [(TRINARY, 0) + D, (SCALE, 0) + D, (SCALE, 1) + D, (RAW, 1) + D]),
    ("rgb16.png", dict(kind="png", color_type=2, bit_depth=16, samples=s3(RED, GREEN, BLUE) * 256 + (s3(RED, GREEN, BLUE) * 7 + 3) % 256),
     [(SCALE, 0) + D, (RAW, 0) + D]),
    ("rgba.png", dict(kind="png", color_type=6, bit_depth=8, samples=s3(RED, GREEN, BLUE, ALPHA)),
     [(TRINARY, 0) + D, (TRINARY, 1) + D, (SCALE, 0) + D, (SCALE, 1) + D, (RAW, 0) + D, (RAW, 1) + D]),
    ("palette_gray.png", dict(kind="png", color_type=3, bit_depth=8, samples=GRAY[:, :, None], plte=GRAY_PLTE),
     [(TRINARY, 0) + D, (SCALE, 1) + D, (RAW, 0) + D]),
    ("palette_color.png", dict(kind="png", color_type=3, bit_depth=8, samples=GRAY[:, :, None], plte=COLOR_PLTE),
     [(TRINARY, 0) + D, (TRINARY, 1) + D, (SCALE, 0) + D, (RAW, 1) + D]),
    ("palette4.png", dict(kind="png", color_type=3, bit_depth=4, samples=IDX16[:, :, None], plte=PLTE16),
     [(TRINARY, 1) + D, (RAW, 0) + D]),
    # One fully transparent entry: SDL keeps the palette (colour key).
    ("palette_colorkey.png", dict(kind="png", color_type=3, bit_depth=8, samples=GRAY[:, :, None], plte=COLOR_PLTE,
                                  trns=bytes([255] * 50 + [0])),
     [(TRINARY, 0) + D, (SCALE, 0) + D]),
    # tRNS present but every entry opaque: SDL still keeps the palette.
    ("palette_opaque_trns.png", dict(kind="png", color_type=3, bit_depth=8, samples=GRAY[:, :, None], plte=COLOR_PLTE,
                                     trns=bytes([255] * 20)),
     [(TRINARY, 0) + D, (RAW, 0) + D]),
    # Translucent entries: expanded to RGBA with Amask.
    ("palette_alpha.png", dict(kind="png", color_type=3, bit_depth=8, samples=GRAY[:, :, None], plte=COLOR_PLTE,
                               trns=bytes([_ALPHAS[i % 8] for i in range(200)])),
     [(TRINARY, 0) + D, (SCALE, 0) + D, (SCALE, 1) + D, (RAW, 0) + D]),
    # Two fully transparent entries, no translucency: also expanded.
    ("palette_two_keys.png", dict(kind="png", color_type=3, bit_depth=8, samples=GRAY[:, :, None], plte=COLOR_PLTE,
                                  trns=bytes([0, 255, 255, 0])),
     [(SCALE, 1) + D]),
]


def pil_check(name, spec, path):
    """PIL reads the written PNG back to the samples we encoded."""
    im = Image.open(path)
    im.load()
    s = spec["samples"]
    ct, bd = spec["color_type"], spec["bit_depth"]
    a = np.array(im).astype(np.int64)
    if ct in (0, 3):
        want = s[:, :, 0]
        if ct == 0 and bd == 1:
            a = a.astype(np.int64)
        elif ct == 0 and bd in (2, 4):
            want = want * (255 // ((1 << bd) - 1))  # PIL scales 2/4-bit gray like libpng
        elif ct == 0 and bd == 16:
            assert im.mode in ("I", "I;16"), im.mode
        if ct == 3:
            assert im.mode == "P", im.mode
            pal = im.getpalette()
            for i, rgb in enumerate(spec["plte"]):
                assert tuple(pal[3 * i:3 * i + 3]) == tuple(rgb), (name, i)
    elif ct == 2 and bd == 16:
        want = s >> 8
    else:
        want = s
    if not np.array_equal(a, want):
        sys.exit("%s: PIL decodes different samples (mode %s)" % (name, im.mode))
    trns = spec.get("trns")
    if trns is not None:
        assert "transparency" in im.info, name


def main():
    os.makedirs(OUT, exist_ok=True)
    for f in os.listdir(OUT):
        os.remove(os.path.join(OUT, f))
    cases = []
    for n_img, (name, spec, configs) in enumerate(IMAGES):
        path = os.path.join(OUT, name)
        if spec["kind"] == "pgm":
            data = pgm_bytes(spec["samples"][:, :, 0], spec["maxval"], spec["ascii"])
        else:
            data = png_bytes(spec["samples"], spec["bit_depth"], spec["color_type"], spec.get("plte"), spec.get("trns"))
        with open(path, "wb") as f:
            f.write(data)
        if spec["kind"] == "png":
            pil_check(name, spec, path)
        pixels, amask = sdl_surface(spec)
        stem = name.rsplit(".", 1)[0]
        for n_cfg, (mode, negate, occ_th, free_th) in enumerate(configs):
            case = "%s.%s.n%d%s" % (stem, mode or "nomode", negate, "" if (occ_th, free_th) == D else ".t%g-%g" % (occ_th, free_th))
            resolution = [0.05, 0.1, 0.25, 1.0, 0.5][(n_img + n_cfg) % 5]
            origin = [(-1.5, 2.25), (0.0, 0.0), (10.0, -3.5), (-0.35, -0.15)][(n_img + n_cfg) % 4]
            with open(os.path.join(OUT, case + ".yaml"), "w") as f:
                f.write("image: %s\n" % name)
                f.write("resolution: %r\n" % resolution)
                f.write("origin: [%r, %r, 0.0]\n" % origin)
                f.write("negate: %d\n" % negate)
                f.write("occupied_thresh: %r\n" % occ_th)
                f.write("free_thresh: %r\n" % free_th)
                if mode is not None:
                    f.write("mode: %s\n" % mode)
            m = mode or TRINARY
            values = load_map_from_file(pixels, amask, negate, occ_th, free_th, m)
            free = free_mask(values, m, free_th)
            with open(os.path.join(OUT, case + ".expected"), "w") as f:
                f.write("%d %d\n%r %r %r\n" % (W, H, resolution, origin[0], origin[1]))
                for r in range(H):
                    f.write(" ".join("%d" % v for v in values[r * W:(r + 1) * W]) + "\n")
                for r in range(H):
                    f.write(" ".join("%d" % v for v in free[r * W:(r + 1) * W]) + "\n")
            cases.append(case)
    with open(os.path.join(OUT, "cases.txt"), "w") as f:
        f.write("".join(c + "\n" for c in cases))
    print("%d images, %d cases in %s" % (len(IMAGES), len(cases), OUT))


if __name__ == "__main__":
    main()
