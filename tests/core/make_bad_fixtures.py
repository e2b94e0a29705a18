#!/usr/bin/python3
"""Writes tests/core/fixtures/bad/: scenarios and maps that must be rejected.

  cases/<case>.yaml   a scenario (what `gather info`, `gather_agent --id 0` and
                      the OC node are given); some refer to broken maps
  maps/               a small valid map (ok.yaml + ok.pgm) and broken ones
  cases.txt           one case a line: <scenario file in cases/> <file name the
                      error must contain> <word(s) naming the problem>

Used by tests/core/bad_input_test.cpp (library level) and
tests/cli/bad_input.sh (any command: exit 2, one stderr line naming the file).
Run: /usr/bin/python3 tests/core/make_bad_fixtures.py
"""
import os
import shutil
import struct
import zlib

HERE = os.path.dirname(os.path.abspath(__file__))
OUT = os.path.join(HERE, "fixtures", "bad")
CASES = os.path.join(OUT, "cases")
MAPS = os.path.join(OUT, "maps")

# 10 x 8 map, 0.5 m/cell, origin [0, 0]: walls all round, free inside,
# an obstacle block. Image row 0 = top.
WALL, FREE = 0, 254
IMG = [[WALL] * 10] + [[WALL] + [FREE] * 8 + [WALL] for _ in range(6)] + [[WALL] * 10]
IMG[2][5] = IMG[2][6] = IMG[3][5] = IMG[3][6] = WALL


def pgm(rows, maxval=255):
    return b"P5\n%d %d\n%d\n" % (len(rows[0]), len(rows), maxval) + bytes(v for r in rows for v in r)


def png_chunk(tag, data):
    return struct.pack(">I", len(data)) + tag + data + struct.pack(">I", zlib.crc32(tag + data) & 0xFFFFFFFF)


def png(rows):
    raw = b"".join(b"\x00" + bytes(r) for r in rows)

    def chunk(tag, data):
        return struct.pack(">I", len(data)) + tag + data + struct.pack(">I", zlib.crc32(tag + data) & 0xFFFFFFFF)

    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", len(rows[0]), len(rows), 8, 0, 0, 0, 0)) +
            chunk(b"IDAT", zlib.compress(raw, 0)) + chunk(b"IEND", b""))


def map_yaml(image, **over):
    keys = dict(image=image, resolution="0.5", origin="[0.0, 0.0, 0.0]", negate="0",
                occupied_thresh="0.65", free_thresh="0.196")
    keys.update(over)
    return "".join("%s: %s\n" % (k, v) for k, v in keys.items() if v is not None)


def scenario(map_file="../maps/ok.yaml", oc="[1.25, 1.25]", extra=""):
    text = ""
    if map_file is not None:
        text += "map: %s\n" % map_file
    if oc is not None:
        text += "oc: %s\n" % oc
    return text + "team:\n  agents: 3\n  speed: 0.5\n" + extra


def write(path, data):
    with open(path, "wb") as f:
        f.write(data.encode() if isinstance(data, str) else data)


def main():
    shutil.rmtree(OUT, ignore_errors=True)
    os.makedirs(CASES)
    os.makedirs(MAPS)

    # Maps.
    write(os.path.join(MAPS, "ok.pgm"), pgm(IMG))
    write(os.path.join(MAPS, "ok.yaml"), map_yaml("ok.pgm"))
    maps = {
        "missing_image.yaml": map_yaml("nonexistent.pgm"),
        "empty_image_path.yaml": map_yaml('""'),
        # tests/cli/bad_flags.sh: a scenario whose automatic period is over kMaxPeriod
        "kilometre_cells.yaml": map_yaml("ok.pgm", resolution="1000"),
        "unknown_format.yaml": map_yaml("not_an_image.pgm"),
        "empty_image.yaml": map_yaml("empty.pgm"),
        "truncated_p5.yaml": map_yaml("truncated_p5.pgm"),
        "truncated_p2.yaml": map_yaml("truncated_p2.pgm"),
        "truncated_png.yaml": map_yaml("truncated.png"),
        "png_huge_header.yaml": map_yaml("huge_header.png"),
        "pgm16.yaml": map_yaml("pgm16.pgm"),
        "missing_key.yaml": map_yaml("ok.pgm", resolution=None),
        "unknown_key.yaml": map_yaml("ok.pgm") + "occupied_threshold: 0.7\n",
        "resolution_zero.yaml": map_yaml("ok.pgm", resolution="0"),
        "resolution_negative.yaml": map_yaml("ok.pgm", resolution="-0.05"),
        "thresholds_order.yaml": map_yaml("ok.pgm", occupied_thresh="0.3", free_thresh="0.7"),
        "malformed.yaml": "image: ok.pgm\nresolution: [0.5\norigin: [0, 0, 0]\n",
        "wrong_type.yaml": map_yaml("ok.pgm", resolution="fine"),
        "bad_mode.yaml": map_yaml("ok.pgm", mode="ternary"),
        "rotated.yaml": map_yaml("ok.pgm", origin="[0.0, 0.0, 1.57]"),
        "pgm_header_20000.yaml": map_yaml("header_20000.pgm"),
        "png_decodes_huge.yaml": map_yaml("decodes_huge.png"),
        "image_dev_zero.yaml": map_yaml("/dev/zero"),
        "image_directory.yaml": map_yaml("."),
        "resolution_tiny.yaml": map_yaml("ok.pgm", resolution="1e-300"),
        "origin_nan.yaml": map_yaml("ok.pgm", origin="[.nan, 0.0, 0.0]"),
        "origin_huge.yaml": map_yaml("ok.pgm", origin="[1e300, 0.0, 0.0]"),
    }
    for name, text in maps.items():
        write(os.path.join(MAPS, name), text)
    write(os.path.join(MAPS, "not_an_image.pgm"), "this is not an image\n")
    write(os.path.join(MAPS, "empty.pgm"), b"")
    full = pgm(IMG)
    write(os.path.join(MAPS, "truncated_p5.pgm"), full[:-17])
    p2 = "P2\n10 8\n255\n" + "\n".join(" ".join(str(v) for v in r) for r in IMG[:5]) + "\n"
    write(os.path.join(MAPS, "truncated_p2.pgm"), p2)
    whole = png(IMG)
    write(os.path.join(MAPS, "truncated.png"), whole[:len(whole) // 2])
    # A valid header claiming 100000x100000 pixels over a few bytes of data:
    # must be refused before anything that size is allocated.
    ihdr = struct.pack(">IIBBBBB", 100000, 100000, 8, 0, 0, 0, 0)
    write(os.path.join(MAPS, "huge_header.png"), b"\x89PNG\r\n\x1a\n" + png_chunk(b"IHDR", ihdr) +
          png_chunk(b"IDAT", zlib.compress(b"\0" * 100)) + png_chunk(b"IEND", b""))
    write(os.path.join(MAPS, "pgm16.pgm"), b"P5\n2 2\n65535\n" + b"\x00" * 8)
    # A 19-byte PGM header claiming 20000 x 20000 pixels: refused by the
    # pixel limit before anything that size is allocated.
    write(os.path.join(MAPS, "header_20000.pgm"), b"P5\n20000 20000\n255\n")
    # A small PNG (zlib packs 9000 x 9000 zero bytes into ~80 KB) that
    # decodes to 81 M pixels: refused by the pixel limit from its header.
    ihdr = struct.pack(">IIBBBBB", 9000, 9000, 8, 0, 0, 0, 0)
    comp = zlib.compressobj(9)
    row = b"\0" * 9001
    idat = b"".join(comp.compress(row) for _ in range(9000)) + comp.flush()
    write(os.path.join(MAPS, "decodes_huge.png"), b"\x89PNG\r\n\x1a\n" + png_chunk(b"IHDR", ihdr) +
          png_chunk(b"IDAT", idat) + png_chunk(b"IEND", b""))

    # Scenarios: (case, text or None for "file absent", file the message must name, problem words).
    cases = [
        ("missing_scenario", None, "missing_scenario.yaml", "cannot open"),
        ("missing_map_yaml", scenario(map_file="../maps/nonexistent.yaml"), "nonexistent.yaml", "cannot open"),
        ("missing_image", scenario(map_file="../maps/missing_image.yaml"), "nonexistent.pgm", "cannot open"),
        ("unknown_image_format", scenario(map_file="../maps/unknown_format.yaml"), "not_an_image.pgm", "unknown image format"),
        ("empty_image", scenario(map_file="../maps/empty_image.yaml"), "empty.pgm", "empty"),
        ("truncated_p5", scenario(map_file="../maps/truncated_p5.yaml"), "truncated_p5.pgm", "truncated"),
        ("truncated_p2", scenario(map_file="../maps/truncated_p2.yaml"), "truncated_p2.pgm", "truncated"),
        ("truncated_png", scenario(map_file="../maps/truncated_png.yaml"), "truncated.png", "truncated"),
        ("png_huge_header", scenario(map_file="../maps/png_huge_header.yaml"), "huge_header.png", "limit"),
        ("pgm_16bit", scenario(map_file="../maps/pgm16.yaml"), "pgm16.pgm", "maxval"),
        ("missing_key_map", scenario(map_file=None), "missing_key_map.yaml", "missing key 'map'"),
        ("missing_key_oc", scenario(map_file="../maps/ok.yaml", oc=None), "missing_key_oc.yaml", "missing key 'oc'"),
        ("missing_map_yaml_key", scenario(map_file="../maps/missing_key.yaml"), "missing_key.yaml", "missing key 'resolution'"),
        ("unknown_key", scenario(extra="seed: 3\n"), "unknown_key.yaml", "unknown key 'seed'"),
        ("unknown_key_team", scenario().replace("  speed: 0.5\n", "  sped: 0.5\n"), "unknown_key_team.yaml",
         "unknown key 'team.sped'"),
        ("unknown_key_radio", scenario(extra="radio:\n  exponent: 3.0\n  wall_loss: 5.0\n"), "unknown_key_radio.yaml",
         "unknown key 'radio.wall_loss'"),
        ("unknown_key_planner", scenario(extra="planner:\n  method: [bap]\n"), "unknown_key_planner.yaml",
         "unknown key 'planner.method'"),
        ("max_cells_negative", scenario(extra="planner:\n  max_cells: -5\n"), "max_cells_negative.yaml",
         "planner.max_cells"),
        ("refresh_unknown", scenario(extra="planner:\n  refresh: age\n"), "refresh_unknown.yaml",
         "planner.refresh"),
        ("bitrate_negative", scenario(extra="radio:\n  bitrate_bps: -1\n"), "bitrate_negative.yaml",
         "radio.bitrate_bps"),
        ("pgm_header_20000", scenario(map_file="../maps/pgm_header_20000.yaml"), "header_20000.pgm", "limit"),
        ("png_decodes_huge", scenario(map_file="../maps/png_decodes_huge.yaml"), "decodes_huge.png", "limit"),
        ("image_dev_zero", scenario(map_file="../maps/image_dev_zero.yaml"), "/dev/zero", "not a regular file"),
        ("image_directory", scenario(map_file="../maps/image_directory.yaml"), "maps/.", "directory"),
        ("scenario_dev_zero", "@/dev/zero", "scenario_dev_zero.yaml", "not a regular file"),
        ("resolution_tiny", scenario(map_file="../maps/resolution_tiny.yaml"), "resolution_tiny.yaml", "resolution"),
        ("origin_nan", scenario(map_file="../maps/origin_nan.yaml"), "origin_nan.yaml", "origin"),
        ("origin_huge", scenario(map_file="../maps/origin_huge.yaml"), "origin_huge.yaml", "origin"),
        ("oc_nan", scenario(oc="[.nan, 1.0]"), "oc_nan.yaml", "oc x"),
        ("speed_tiny", scenario().replace("speed: 0.5", "speed: 1e-9"), "speed_tiny.yaml", "team.speed"),
        ("max_walls_huge", scenario(extra="radio:\n  max_walls: 2000000000\n  wall_loss_db: 0\n"),
         "max_walls_huge.yaml", "radio.max_walls"),
        ("tx_power_nan", scenario(extra="radio:\n  tx_power_dbm: .nan\n"), "tx_power_nan.yaml", "radio.tx_power_dbm"),
        ("sensitivity_inf", scenario(extra="radio:\n  sensitivity_dbm: -.inf\n"), "sensitivity_inf.yaml",
         "radio.sensitivity_dbm"),
        ("cycles_huge", scenario(extra="mission:\n  cycles: 2147483647\n"), "cycles_huge.yaml", "mission.cycles"),
        ("alpha_inf", scenario(extra="planner:\n  alpha: .inf\n"), "alpha_inf.yaml", "planner.alpha"),
        ("bytes_per_goal_nan", scenario(extra="mission:\n  bytes_per_goal: .nan\n"), "bytes_per_goal_nan.yaml",
         "mission.bytes_per_goal"),
        ("unknown_map_yaml_key", scenario(map_file="../maps/unknown_key.yaml"), "unknown_key.yaml",
         "unknown key 'occupied_threshold'"),
        ("resolution_zero", scenario(map_file="../maps/resolution_zero.yaml"), "resolution_zero.yaml", "resolution"),
        ("resolution_negative", scenario(map_file="../maps/resolution_negative.yaml"), "resolution_negative.yaml",
         "resolution"),
        ("thresholds_out_of_order", scenario(map_file="../maps/thresholds_order.yaml"), "thresholds_order.yaml",
         "thresholds"),
        ("map_mode_unknown", scenario(map_file="../maps/bad_mode.yaml"), "bad_mode.yaml", "mode"),
        ("map_origin_rotated", scenario(map_file="../maps/rotated.yaml"), "rotated.yaml", "yaw"),
        ("oc_outside_map", scenario(oc="[7.0, 1.0]"), "oc_outside_map.yaml", "outside"),
        ("oc_negative_outside_map", scenario(oc="[-0.1, 1.0]"), "oc_negative_outside_map.yaml", "outside"),
        ("oc_in_wall", scenario(oc="[0.25, 0.25]"), "oc_in_wall.yaml", "obstacle"),
        ("oc_in_obstacle", scenario(oc="[2.75, 2.25]"), "oc_in_obstacle.yaml", "obstacle"),
        ("oc_not_a_pair", scenario(oc="[1.25]"), "oc_not_a_pair.yaml", "oc must be"),
        ("agents_zero", scenario().replace("agents: 3", "agents: 0"), "agents_zero.yaml", "agents"),
        ("agents_negative", scenario().replace("agents: 3", "agents: -2"), "agents_negative.yaml", "agents"),
        ("agents_wrong_type", scenario().replace("agents: 3", 'agents: "many"'), "agents_wrong_type.yaml", "wrong type"),
        ("agents_fraction", scenario().replace("agents: 3", "agents: 2.5"), "agents_fraction.yaml", "wrong type"),
        ("oc_wrong_type", scenario(oc="here"), "oc_wrong_type.yaml", "wrong type"),
        ("team_not_a_mapping", "map: ../maps/ok.yaml\noc: [1.25, 1.25]\nteam: 5\n", "team_not_a_mapping.yaml", "mapping"),
        ("map_yaml_wrong_type", scenario(map_file="../maps/wrong_type.yaml"), "wrong_type.yaml", "wrong type"),
        ("malformed_yaml", "map: ../maps/ok.yaml\noc: [1.25, 1.25\nteam:\n  agents: 3\n", "malformed_yaml.yaml", "syntax"),
        ("malformed_yaml_tab", "map: ../maps/ok.yaml\n\toc: [1.25, 1.25]\n", "malformed_yaml_tab.yaml", "syntax"),
        ("malformed_map_yaml", scenario(map_file="../maps/malformed.yaml"), "malformed.yaml", "syntax"),
        ("not_a_mapping", "- map: ../maps/ok.yaml\n- oc: [1, 1]\n", "not_a_mapping.yaml", "mapping"),
        ("empty_scenario", "", "empty_scenario.yaml", "mapping"),
        ("complex_key", scenario(extra="[a, b]: 1\n"), "complex_key.yaml", "key"),
        ("empty_map_path", scenario(map_file='""'), "empty_map_path.yaml", "key 'map' is empty"),
        ("empty_image_path", scenario(map_file="../maps/empty_image_path.yaml"), "empty_image_path.yaml",
         "key 'image' is empty"),
        ("period_over_max", scenario(extra="mission:\n  period: 200000\n"), "period_over_max.yaml", "mission.period"),
        ("yaml_alias", scenario(extra="radio:\n  tx_power_dbm: &p 0\n  ref_loss_db: *p\n"), "yaml_alias.yaml",
         "aliases"),
    ]
    lines = ["# <scenario in cases/> <file the one-line error must name> <words naming the problem>\n"]
    for case, text, named, words in cases:
        fname = case + ".yaml"
        if text is not None and text.startswith("@"):  # a symlink to a device
            os.symlink(text[1:], os.path.join(CASES, fname))
        elif text is not None:
            write(os.path.join(CASES, fname), text)
        lines.append("%-28s %-28s %s\n" % (fname, named, words))
    write(os.path.join(OUT, "cases.txt"), "".join(lines))
    print("%d bad cases in %s" % (len(cases), OUT))


if __name__ == "__main__":
    main()
