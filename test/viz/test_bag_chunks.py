#!/usr/bin/python3
"""Tests of the analysis' sequential bag reader (src/preadaptive_mrac/analysis/bag_chunks.py)
against rosbag's own read_messages, and of the fallback to read_messages.

Run:  /usr/bin/python3 -m unittest discover -s test/viz -p 'test_bag_chunks.py' -v
"""

import io
import json
import os
import shutil
import sys
import tempfile
import unittest
from unittest import mock

HERE = os.path.dirname(os.path.abspath(__file__))
PKG = os.path.abspath(os.path.join(HERE, '..', '..'))
sys.path.insert(0, HERE)
sys.path.insert(0, os.path.join(PKG, 'src'))  # the package of this source tree

import synthetic  # noqa: E402
from preadaptive_mrac import analysis as pa  # noqa: E402
from preadaptive_mrac.analysis import bag_chunks, bags  # noqa: E402

WANTED = ['/a/status', '/b/value', '/c/elevator_cmd', '/two']


def write_mixed_bag(path, compression='none'):
    """Several topics over many small chunks: ties in time across topics and connections, a
    message out of time order on one connection (the chunk's index puts it in time order), a
    topic with two connections (two publishers: rosbag's Python writer keeps one connection per
    topic, so the second one is made by hand) and a topic nobody asks for."""
    import rosbag
    import rospy
    from std_msgs.msg import Float64, String

    Elevator = synthetic.load_msg_classes()['ElevatorCommand']  # a header and plain fields
    counts = {}
    with rosbag.Bag(path, 'w', chunk_threshold=1024, compression=compression) as b:
        pubs = [None, None]

        def put(topic, msg, t):
            b.write(topic, msg, t)
            counts[topic] = counts.get(topic, 0) + 1

        for i in range(300):
            t = rospy.Time(1000, 1000000 * (i // 2))  # pairs of equal times
            put('/a/status', String('s%d' % i), t)
            if i % 3 == 0:
                put('/b/value', Float64(i * 0.1), t)
            if i % 50 == 7:  # late: bag time before the previous message's
                put('/a/status', String('late%d' % i), t - rospy.Duration(0, 5000000))
            put('/unwanted', Float64(i), t)
            if i % 4 == 1:
                e = Elevator(step=i, u=-0.01 * i, u_baseline=0.5, safe=i % 8 == 1)
                e.header.seq, e.header.stamp, e.header.frame_id = i, t, 'f%d' % i
                put('/c/elevator_cmd', e, t)
            k = i % 2 if i < 200 else 1  # the second publisher alone at the end
            b._topic_connections.pop('/two', None)
            if pubs[k] is not None:
                b._topic_connections['/two'] = pubs[k]
            put('/two', String('p%d_%d' % (k, i)), t)
            pubs[k] = b._topic_connections['/two']
    return path, counts


def rosbag_messages(path, topics):
    import rosbag

    out = {}
    with rosbag.Bag(path, 'r') as b:
        for topic, msg, t in b.read_messages(topics=topics):
            out.setdefault(topic, []).append((msg, t.to_sec()))
    return out


def as_bytes(pairs):
    """(type, serialized message, bag time) of each pair, in order."""
    out = []
    for msg, t in pairs:
        buf = io.BytesIO()
        msg.serialize(buf)
        out.append((msg._type, buf.getvalue(), t))
    return out


class ChunkReaderTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.d = tempfile.mkdtemp(prefix='pmrac_bag_chunks_')

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.d, ignore_errors=True)

    def fast(self, path, topics):
        import rosbag

        with rosbag.Bag(path, 'r', skip_index=True) as b:
            return bag_chunks.ChunkReader(b).read(topics)

    def test_same_messages_in_the_same_order_as_read_messages(self):
        path, counts = write_mixed_bag(os.path.join(self.d, 'mixed.bag'))
        import rosbag

        with rosbag.Bag(path, 'r') as b:
            self.assertGreater(len(b._chunks), 20)
            self.assertEqual(b.get_type_and_topic_info().topics['/two'].connections, 2)
        got = self.fast(path, WANTED)
        ref = rosbag_messages(path, WANTED)
        self.assertEqual(sorted(got), WANTED)
        for topic in WANTED:
            self.assertEqual(len(got[topic]), counts[topic], topic)
            self.assertEqual(as_bytes(got[topic]), as_bytes(ref[topic]), topic)
        # the elevator commands were made empty (header and stamp without defaults) before
        # deserialize(), the others with cls()
        with rosbag.Bag(path, 'r', skip_index=True) as b:
            made = {
                c.topic: bag_chunks._blank(rosbag.bag._get_message_type(c))
                for c in b._connections.values()
            }
        self.assertFalse(isinstance(made['/c/elevator_cmd'], type))
        self.assertTrue(isinstance(made['/a/status'], type))
        self.assertEqual(got['/c/elevator_cmd'][3][0].header.frame_id, 'f13')
        # the order is the index's, not the file's: rosbag's Python writer sorts a chunk's
        # index by time, so the late message (written after s7) is read before it
        names = [m.data for m, _ in got['/a/status']]
        self.assertLess(names.index('late7'), names.index('s7'))

    def test_a_dropped_or_moved_message_is_seen(self):
        """The comparison above fails when the reader loses or swaps a message."""
        path, _ = write_mixed_bag(os.path.join(self.d, 'mixed2.bag'))
        ref = as_bytes(rosbag_messages(path, WANTED)['/a/status'])
        got = self.fast(path, WANTED)['/a/status']
        self.assertEqual(as_bytes(got), ref)
        self.assertNotEqual(as_bytes(got[:-1]), ref)
        self.assertNotEqual(as_bytes([got[1], got[0]] + got[2:]), ref)

    def test_compressed_bags_fall_back_to_read_messages(self):
        plain = os.path.join(self.d, 'plain.bag')
        sim = synthetic.simulate('pa', seed=1, t_end=6.0)
        synthetic.write_bag(plain, {'rac': sim, 'pa': sim})
        expect = json.dumps([pa.run_metrics(r) for r in pa.load_runs(plain)], sort_keys=True)
        import rosbag

        for compression in ('bz2', 'lz4'):
            path = os.path.join(self.d, compression + '.bag')
            with rosbag.Bag(plain) as src, rosbag.Bag(path, 'w', compression=compression) as dst:
                for topic, msg, t in src.read_messages(raw=True):
                    dst.write(topic, msg, t, raw=True)
            with rosbag.Bag(path, 'r', skip_index=True) as b:
                with self.assertRaises(bag_chunks.Unsupported):
                    bag_chunks.ChunkReader(b)
            runs = pa.load_runs(path)
            got = json.dumps([pa.run_metrics(r) for r in runs], sort_keys=True)
            self.assertEqual(got, expect.replace('plain.bag', compression + '.bag'), compression)

    def test_runs_from_the_reader_and_from_read_messages_agree(self):
        path = os.path.join(self.d, 'compare.bag')
        sim = synthetic.simulate('pa', seed=1, t_end=6.0)
        synthetic.write_bag(path, {'rac': sim, 'pa': sim})
        calls = []
        real = bag_chunks.ChunkReader.read

        def spy(self, topics):
            calls.append(topics)
            return real(self, topics)

        with mock.patch.object(bag_chunks.ChunkReader, 'read', spy):
            fast = json.dumps([pa.run_metrics(r) for r in bags._load_bag(path)], sort_keys=True)
        self.assertEqual(len(calls), 1)  # the chunk reader was used

        def refuse(self, bag):
            raise bag_chunks.Unsupported('test')

        with mock.patch.object(bag_chunks.ChunkReader, '__init__', refuse):
            slow = json.dumps([pa.run_metrics(r) for r in bags._load_bag(path)], sort_keys=True)
        self.assertEqual(fast, slow)

        # the reader failing part-way (a record it does not expect, or a fault of its own):
        # read_messages from a reopened bag
        def late(self, topics):
            raise RuntimeError('test')

        with mock.patch.object(bag_chunks.ChunkReader, 'read', late):
            reread = json.dumps([pa.run_metrics(r) for r in bags._load_bag(path)], sort_keys=True)
        self.assertEqual(reread, slow)


if __name__ == '__main__':
    unittest.main()
