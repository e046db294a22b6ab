"""Message classes built at run time from the definitions publishers send (rospy.AnyMsg +
genpy), so the viz runs without the generated Python messages and with old bags."""

import threading

import genpy.dynamic
from geometry_msgs.msg import TransformStamped
import rospy


EVENT_NAMES = ('onset', 'recovered', 'ignored_onset', 'ignored_recovery', 'decision')


# genpy's code generator keeps the struct patterns of the message being generated in a
# module-level list, so two threads generating at once corrupt each other's modules (a
# class whose deserialize() calls a _get_struct_* that was never written). rospy runs each
# subscription's callbacks in its own thread: generate under one lock.
_GENERATE_LOCK = threading.Lock()


class DynamicSubscriber:
    """Subscribes with rospy.AnyMsg and deserialises with a class generated from the
    connection header's message definition (cached per type and md5). A message whose
    publisher sent no definition is skipped, with a warning every 10 s naming `warn_label`
    (None: silently)."""

    def __init__(self, topic, callback, queue_size, warn_label='viz_markers'):
        self._callback = callback
        self._warn_label = warn_label
        self._classes = {}
        self._sub = rospy.Subscriber(topic, rospy.AnyMsg, self._on_raw, queue_size=queue_size)

    def _on_raw(self, raw):
        hdr = getattr(raw, '_connection_header', None) or {}
        key = (hdr.get('type'), hdr.get('md5sum'))
        cls = self._classes.get(key)
        if cls is None:
            if not key[0] or 'message_definition' not in hdr:
                if self._warn_label is not None:
                    rospy.logwarn_throttle(
                        10.0,
                        '%s: no message definition on %s'
                        % (self._warn_label, self._sub.resolved_name),
                    )
                return
            with _GENERATE_LOCK:
                cls = genpy.dynamic.generate_dynamic(key[0], hdr['message_definition'])[key[0]]
            self._classes[key] = cls
        msg = cls()
        msg.deserialize(raw._buff)
        self._callback(msg)


def tf_message_class():
    """tf2_msgs/TFMessage built from geometry_msgs' definition (Debian's ROS has no
    python3-tf2-ros / tf2_msgs Python by default); same md5 as the real one."""
    full = (
        'geometry_msgs/TransformStamped[] transforms\n'
        + '=' * 80
        + '\nMSG: geometry_msgs/TransformStamped\n'
        + TransformStamped._full_text
    )
    with _GENERATE_LOCK:
        return genpy.dynamic.generate_dynamic('tf2_msgs/TFMessage', full)['tf2_msgs/TFMessage']
