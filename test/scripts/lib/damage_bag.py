"""Damage a copy of a bag the ways a disk, a kill or a transfer does (for the analysis tests).

    /usr/bin/python3 test/scripts/lib/damage_bag.py MODE IN OUT

MODE: index   50 bytes flipped in the index (after the header's index_pos)
      spread  10 bits flipped over the file after its header (seeded)
      killed  what a killed recorder leaves: cut at the index, index_pos 0 in the header
      garbage the bag header line and random bytes
"""
import random
import struct
import sys


def index_pos_field(data):
    """(offset of the 8-byte index_pos value, its value) in the file header record."""
    (hlen,) = struct.unpack_from('<I', data, 13)
    pos, end = 17, 17 + hlen
    while pos < end:
        (flen,) = struct.unpack_from('<I', data, pos)
        name, _, value = data[pos + 4 : pos + 4 + flen].partition(b'=')
        if name == b'index_pos':
            at = pos + 4 + len(name) + 1
            return at, struct.unpack('<Q', value)[0]
        pos += 4 + flen
    raise SystemExit('no index_pos in the header')


def main():
    mode, src, dst = sys.argv[1:4]
    data = bytearray(open(src, 'rb').read())
    rng = random.Random(40)
    at, index_pos = index_pos_field(data)
    if mode == 'index':
        for _ in range(50):
            i = rng.randrange(index_pos, len(data))
            data[i] ^= 0xFF
    elif mode == 'spread':
        for _ in range(10):
            i = rng.randrange(4096 + 13, len(data))
            data[i] ^= 1 << rng.randrange(8)
    elif mode == 'killed':
        data = data[:index_pos]
        data[at : at + 8] = struct.pack('<Q', 0)
    elif mode == 'garbage':
        data = bytearray(b'#ROSBAG V2.0\n' + bytes(rng.randrange(256) for _ in range(20000)))
    else:
        raise SystemExit('unknown mode ' + mode)
    open(dst, 'wb').write(bytes(data))


if __name__ == '__main__':
    main()
