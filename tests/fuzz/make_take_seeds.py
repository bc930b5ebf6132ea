#!/usr/bin/env python3
"""Writes the seed corpus for fuzz_take: small frames.bin images built with
Python's struct and zlib.crc32, i.e. independently of the C++ encoder, so
test_core can also check that both agree on the byte layout of take.h."""
import os
import struct
import zlib


def record(kind, index, time_s, fields):
    payload = struct.pack("<I", len(fields))
    for name, shape, values in fields:
        payload += struct.pack("<H", len(name)) + name.encode() + struct.pack("<BB", 1, len(shape))
        payload += struct.pack("<%dI" % len(shape), *shape)
        payload += struct.pack("<%df" % len(values), *values)
    head = struct.pack("<IHHiIdQI", 0x52464C50, 1, kind, index, 0, time_s, len(payload),
                       zlib.crc32(payload))
    return head + struct.pack("<I", zlib.crc32(head)) + payload


def density(n, index):
    return [float(index * 100 + i) * 0.25 for i in range(n)]


here = os.path.join(os.path.dirname(os.path.abspath(__file__)), "corpus", "take")
os.makedirs(here, exist_ok=True)
frames = b"".join(record(1, i, 0.02 * i, [("density", [4, 4], density(16, i))]) for i in range(3))
seeds = {
    "three_frames.bin": frames,
    "frame_velocity_checkpoint.bin":
        record(1, 0, 0.0, [("density", [2, 2, 2], density(8, 0)),
                           ("velocity", [3, 2, 2, 2], density(24, 1))]) +
        record(3, 0, 0.0, []) + record(2, 5, 1.5, [("preview", [1], [0.5])]),
    "torn_tail.bin": frames[:-7],
    "empty.bin": b"",
}
for name, data in seeds.items():
    with open(os.path.join(here, name), "wb") as f:
        f.write(data)
