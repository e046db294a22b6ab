"""A sequential reader of ROS bag 2.0 files for analyze_bag: each chunk read once, in file order,
its message records located through the index records that follow it (read here, not by
rosbag), and only the wanted topics deserialized (with the class rosbag itself would use).

rosbag's `Bag.read_messages` seeks and parses one record per message and builds rospy Time
objects for every index entry; this reader gives the same (message, bag time) pairs per topic in
the same order as `read_messages(topics=...)` does:
  - rosbag's index of a connection is its index records in chunk order (not sorted), and
    read_messages merges the connections' indexes with heapq.merge on the entry time; heapq.merge
    keeps each input's order, and the entries of one topic come out as the merge of that topic's
    connections alone (ties: the connection listed first), which is what is done here;
  - the bag time is the `time` field of the message record (as rosbag returns it), as float
    seconds computed as rospy's to_sec() does (secs + nsecs / 1e9).
Anything else (compressed or encrypted chunks, other versions, index data that does not add up,
records not laid out as expected) raises Unsupported, and the caller reads the bag with rosbag.
"""

import heapq
import struct

import numpy as np

_OP_MSG_DATA = 2
_OP_INDEX_DATA = 4
_OP_CONNECTION = 7
_INDEX_DTYPE = np.dtype([('sec', '<u4'), ('nsec', '<u4'), ('off', '<u4')])

_FIELDS = {
    'conn': list(struct.pack('<I', 9)) + list(b'conn=') + [None] * 4,
    'op': list(struct.pack('<I', 4)) + list(b'op=') + [_OP_MSG_DATA],
    'time': list(struct.pack('<I', 13)) + list(b'time=') + [None] * 8,
}


def _layout(order):
    """A message record header of the three fields in this order: (byte template with None
    for any byte, offset of the connection id)."""
    t = list(struct.pack('<I', 38))
    for name in order:
        if name == 'conn':
            conn_at = len(t) + 9
        t += _FIELDS[name]
    t += [None] * 4  # the data length
    fixed = np.array([i for i, v in enumerate(t) if v is not None])
    return fixed, np.array([t[i] for i in fixed], dtype=np.uint8), conn_at


# A message record as rosbag's C++ writer and src/ros/bag_writer.cpp write it (the fields in
# std::map order) and as rosbag's Python writer does (op first); the time and the data length
# are at the same places in both.
_LAYOUTS = [_layout(('conn', 'op', 'time')), _layout(('op', 'conn', 'time'))]
_SEC_AT, _NSEC_AT, _LEN_AT = 34, 38, 42
_HEAD = 46  # bytes before the message data


_PLAIN = {
    'bool',
    'byte',
    'char',
    'int8',
    'uint8',
    'int16',
    'uint16',
    'int32',
    'uint32',
    'int64',
    'uint64',
    'float32',
    'float64',
    'string',
}


def _blank(cls):
    """A maker of messages for deserialize(). cls() fills every field with a default that
    deserialize() then overwrites, a genpy Time with type checks for a header's stamp (about
    1 us a message); for a message of a std_msgs/Header first and plain fields (numbers,
    strings, arrays of them: deserialize() assigns each), the message and its header are made
    empty instead. Any other message: cls."""
    types = list(getattr(cls, '_slot_types', []))
    slots = list(getattr(cls, '__slots__', []))
    if not types or types[0] != 'std_msgs/Header' or slots[:1] != ['header']:
        return cls
    if not all(t.split('[')[0] in _PLAIN for t in types[1:]):
        return cls
    header = type(cls().header)
    if list(header.__slots__) != ['seq', 'stamp', 'frame_id'] or list(header._slot_types) != [
        'uint32',
        'time',
        'string',
    ]:
        return cls
    stamp = type(header().stamp)
    new_msg, new_header, new_stamp = cls.__new__, header.__new__, stamp.__new__

    def blank():
        m = new_msg(cls)
        h = new_header(header)
        h.stamp = new_stamp(stamp)
        m.header = h
        return m

    return blank


class Unsupported(Exception):
    """The bag is not one this reader handles; read it with rosbag instead."""


def _header(buf, pos):
    """The fields of the record header at pos: ({name: value bytes}, position after it)."""
    if pos + 4 > len(buf):
        raise Unsupported('record header past the end')
    (n,) = struct.unpack_from('<I', buf, pos)
    pos += 4
    end = pos + n
    if end > len(buf):
        raise Unsupported('record header past the end')
    fields = {}
    while pos < end:
        if pos + 4 > end:
            raise Unsupported('bad header field')
        (fl,) = struct.unpack_from('<I', buf, pos)
        pos += 4
        field = bytes(buf[pos : pos + fl])
        pos += fl
        if pos > end or b'=' not in field:
            raise Unsupported('bad header field')
        name, value = field.split(b'=', 1)
        fields[name] = value
    return fields, end


def _u32(fields, name):
    v = fields.get(name)
    if v is None or len(v) != 4:
        raise Unsupported('header field %s' % name)
    return struct.unpack('<I', v)[0]


class ChunkReader:
    """The index of an indexed, uncompressed, unencrypted bag 2.0 opened by rosbag with
    skip_index=True (rosbag has read the connections, chunk infos and chunk headers)."""

    def __init__(self, bag):
        import rosbag.bag as rb

        if bag._version != 200:
            raise Unsupported('bag version %s' % bag._version)
        if not isinstance(bag._encryptor, rb._ROSBagNoEncryptor):
            raise Unsupported('encrypted bag')
        self.bag = bag
        self._message_type = rb._get_message_type
        self._makers = {}  # connection id -> maker of empty messages
        self.chunks = []  # (data_pos, size, {conn: index entries})
        f = bag._file
        for info in bag._chunks:
            head = bag._chunk_headers.get(info.pos)
            if head is None or head.compression != 'none':
                raise Unsupported('compressed chunk')
            if head.compressed_size != head.uncompressed_size:
                raise Unsupported('chunk sizes differ')
            f.seek(head.data_pos + head.compressed_size)
            index = {}
            for _ in range(len(info.connection_counts)):
                index_head = f.read(4)
                if len(index_head) != 4:
                    raise Unsupported('index past the end')
                (n,) = struct.unpack('<I', index_head)
                raw = index_head + f.read(n + 4)
                fields, pos = _header(raw, 0)
                if fields.get(b'op') != bytes([_OP_INDEX_DATA]) or _u32(fields, b'ver') != 1:
                    raise Unsupported('not an index record')
                conn, count = _u32(fields, b'conn'), _u32(fields, b'count')
                if len(raw) != pos + 4 or struct.unpack_from('<I', raw, pos)[0] != 12 * count:
                    raise Unsupported('index record size')
                if conn not in bag._connections or conn in index:
                    raise Unsupported('index of an unknown connection')
                data = f.read(12 * count)
                if len(data) != 12 * count:
                    raise Unsupported('index past the end')
                index[conn] = np.frombuffer(data, dtype=_INDEX_DTYPE)
            self.chunks.append((head.data_pos, head.compressed_size, index))
        # as rosbag does after reading the index: connections without messages are dropped
        # (get_type_and_topic_info then sees the same connections)
        used = {c for _, _, index in self.chunks for c, e in index.items() if len(e)}
        for c in [c for c in bag._connections if c not in used]:
            del bag._connections[c]

    def read(self, topics):
        """{topic: [(message, bag time [s])]} for the topics, each in read_messages' order."""
        import roslib.names

        conns = []  # in rosbag's connection order
        for c in self.bag._connections.values():
            if c.topic in topics:
                conns.append(c)
            elif roslib.names.canonicalize_name(c.topic) in topics:
                raise Unsupported('topic %s named two ways' % c.topic)
        got = {c.id: ([], [], []) for c in conns}  # conn -> index times [ns], messages, bag times
        f = self.bag._file
        for data_pos, size, index in self.chunks:
            wanted = [c for c in conns if c.id in index and len(index[c.id])]
            if not wanted:
                continue
            f.seek(data_pos)
            buf = f.read(size)
            if len(buf) != size:
                raise Unsupported('chunk past the end')
            for c in wanted:
                self._decode(buf, c, index[c.id], got[c.id])
        out = {}
        for c in conns:
            out.setdefault(c.topic, []).append(c.id)
        result = {}
        for topic, ids in out.items():
            if len(ids) == 1:
                _, msgs, times = got[ids[0]]
                result[topic] = list(zip(msgs, times))
            else:
                streams = [zip(got[i][0], got[i][1], got[i][2]) for i in ids]
                result[topic] = [(m, t) for _, m, t in heapq.merge(*streams, key=lambda x: x[0])]
        return result

    def _decode(self, buf, conn, entries, into):
        index_ns, msgs, times = into
        offs = entries['off'].astype(np.int64)
        if np.any(offs + _HEAD > len(buf)):
            raise Unsupported('index entry past the chunk')
        a = np.frombuffer(buf, dtype=np.uint8)
        g = a[offs[:, None] + np.arange(_HEAD)]
        for fixed, fixed_bytes, conn_at in _LAYOUTS:
            if np.all(g[:, fixed] == fixed_bytes):
                break
        else:
            raise Unsupported('message record laid out otherwise')

        def u32(at):
            return np.ascontiguousarray(g[:, at : at + 4]).view('<u4').ravel()

        if np.any(u32(conn_at) != conn.id):
            raise Unsupported('index entry of another connection')
        sec, nsec, length = u32(_SEC_AT), u32(_NSEC_AT), u32(_LEN_AT).astype(np.int64)
        if np.any(nsec >= 1000000000):
            raise Unsupported('time not canonical')
        start = offs + _HEAD
        if np.any(start + length > len(buf)):
            raise Unsupported('message data past the chunk')
        make = self._makers.get(conn.id)
        if make is None:
            make = self._makers[conn.id] = _blank(self._message_type(conn))
        for s, e in zip(start.tolist(), (start + length).tolist()):
            m = make()
            m.deserialize(buf[s:e])
            msgs.append(m)
        times.extend((sec.astype(np.float64) + nsec.astype(np.float64) / 1e9).tolist())
        index_ns.extend((entries['sec'].astype(np.int64) * 1000000000 + entries['nsec']).tolist())
