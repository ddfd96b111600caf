"""Hand-built ZIP archives for hostile-input tests: members deflated once and repeated (a zip
bomb a few KB on disk), under any name and with whatever sizes the directory should declare."""

from __future__ import annotations

import struct
import zlib

__all__ = ["deflate", "zip_of"]


def deflate(data_chunks, repeat: int = 1) -> tuple[bytes, int, int]:
    """Raw deflate of ``data_chunks`` (bytes) and, ``repeat`` times, of one 8 MB zero block
    compressed once (full flush makes blocks independent): (compressed, crc, size)."""
    comp = zlib.compressobj(9, zlib.DEFLATED, -15)
    out = [comp.compress(data_chunks), comp.flush(zlib.Z_FULL_FLUSH)]
    crc, size = zlib.crc32(data_chunks), len(data_chunks)
    if repeat:
        zeros = bytes(8 << 20)
        block_comp = zlib.compressobj(9, zlib.DEFLATED, -15)
        block = block_comp.compress(zeros) + block_comp.flush(zlib.Z_FULL_FLUSH)
        for _ in range(repeat):
            out.append(block)
            crc = zlib.crc32(zeros, crc)
            size += len(zeros)
    out.append(b"\x03\x00")  # final empty block
    return b"".join(out), crc & 0xFFFFFFFF, size


def zip_of(members: dict[str, tuple[bytes, int, int]]) -> bytes:
    """A ZIP archive of already deflated members (name -> (compressed, crc, size))."""
    local, central, offset = [], [], 0
    for name, (data, crc, size) in members.items():
        encoded = name.encode()
        header = struct.pack("<IHHHHHIIIHH", 0x04034B50, 20, 0, 8, 0, 0x21, crc, len(data), size, len(encoded), 0)
        local.append(header + encoded + data)
        central.append(struct.pack("<IHHHHHHIIIHHHHHII", 0x02014B50, 20, 20, 0, 8, 0, 0x21, crc, len(data), size,
                                   len(encoded), 0, 0, 0, 0, 0, offset) + encoded)
        offset += len(header) + len(encoded) + len(data)
    directory = b"".join(central)
    end = struct.pack("<IHHHHIIH", 0x06054B50, 0, 0, len(central), len(central), len(directory), offset, 0)
    return b"".join(local) + directory + end
