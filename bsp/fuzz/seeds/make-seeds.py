#!/usr/bin/env python3
"""Writes the bsp_reader fuzz target's seeds of the formats no test map is in: Quake 2
(IBSP 38, Qbism QBSP 38), Quake 3 (IBSP 46), Quake BSP2 and 2PSB, and a BSP29 copy of
box_room. Each is the smallest file the reader accepts as its format (a lump directory,
the entities, one world model and one leaf), so the fuzzer starts inside every reader
instead of having to find its magic and version first.

    python3 bsp/fuzz/seeds/make-seeds.py      # from the repository's root
"""
import struct

OUT = "bsp/fuzz/seeds/bsp_reader/"
ENT = b'{\n"classname" "worldspawn"\n}\n{\n"classname" "info_player_start"\n"origin" "0 0 24"\n}\n\0'


def dirfile(header, nlumps, lumps):
    """A file of `header`, a directory of `nlumps` lumps and their bytes (lump 0: entities)."""
    lumps = dict(lumps)
    lumps[0] = ENT
    base = len(header) + 8 * nlumps
    body, entries = b"", []
    for i in range(nlumps):
        data = lumps.get(i, b"")
        entries.append((base + len(body), len(data)))
        body += data
        while len(body) % 4:
            body += b"\0"
    return header + b"".join(struct.pack("<ii", o, n) for o, n in entries) + body


q2model = struct.pack("<9f3i", -64, -64, -64, 64, 64, 64, 0, 0, 0, -1, 0, 0)
q2leaf = struct.pack("<ihh6h4H", 1, -1, 0, -64, -64, -64, 64, 64, 64, 0, 0, 0, 0)
qbleaf = struct.pack("<iii6f4I", 1, -1, 0, -64, -64, -64, 64, 64, 64, 0, 0, 0, 0)
q3model = struct.pack("<6f4i", -64, -64, -64, 64, 64, 64, 0, 0, 0, 0)
q3leaf = struct.pack("<12i", -1, 0, -64, -64, -64, 64, 64, 64, 0, 0, 0, 0)
q1model = struct.pack("<9f7i", -64, -64, -64, 64, 64, 64, 0, 0, 0, -1, -1, -1, -1, 0, 0, 0)
bsp2leaf = struct.pack("<ii6f2I4B", -2, -1, -64, -64, -64, 64, 64, 64, 0, 0, 0, 0, 0, 0)
psbleaf = struct.pack("<ii6h2I4B", -2, -1, -64, -64, -64, 64, 64, 64, 0, 0, 0, 0, 0, 0)

files = {
    "quake2-header-only.bsp": dirfile(b"IBSP" + struct.pack("<i", 38), 19, {13: q2model, 8: q2leaf}),
    "qbism-header-only.bsp": dirfile(b"QBSP" + struct.pack("<i", 38), 19, {13: q2model, 8: qbleaf}),
    "quake3-header-only.bsp": dirfile(b"IBSP" + struct.pack("<i", 46), 17, {7: q3model, 4: q3leaf}),
    "bsp2-header-only.bsp": dirfile(b"BSP2", 15, {14: q1model, 10: bsp2leaf}),
    "2psb-header-only.bsp": dirfile(b"2PSB", 15, {14: q1model, 10: psbleaf}),
}
for name, data in files.items():
    with open(OUT + name, "wb") as f:
        f.write(data)
box = bytearray(open("testdata/maps/box_room.bsp", "rb").read())
box[0] = 29  # the same lumps as version 30: a BSP29 map with Half-Life's hulls
with open(OUT + "box_room-as-bsp29.bsp", "wb") as f:
    f.write(bytes(box))
