#!/usr/bin/python3
"""Checks for the rviz screenshot test (test/viz/rviz_screenshot_test.sh).

    rviz_check.py graph  --markers-topic /aircraft_markers [--tf-topic /tf]
        ROS graph: rviz subscribes to /tf and the marker topic, and a node publishes the
        marker topic with messages arriving (listens for one MarkerArray).
    rviz_check.py shot   --out FILE.png
        Screenshot of the whole X screen ($DISPLAY) with PIL (xcb); falls back to
        ImageMagick's `import -window root`.
    rviz_check.py image  FILE.png [--expect-error]
        Image checks: not blank; rviz's 3D render area found (background 48,48,48) and
        holding the markers' colours; the Displays panel shows no display in the error
        (red) or warning (orange) status colour. With --expect-error the status check is
        inverted (used to prove that the check sees a broken configuration).
    rviz_check.py log    FILE... [--expect-error]
        rviz output: no [ERROR]/[FATAL] log lines.

Each prints lines "PASS: ..." / "FAIL: ..." and exits 0 when all its checks pass, else 1.
"""

import argparse
import os
import re
import subprocess
import sys
import time

BG = (48, 48, 48)  # Background Color of rviz/preadaptive_mrac.rviz
# rviz's StatusProperty colours for the Displays tree (text and icons):
# Error = QColor(178, 23, 46), Warn = QColor(192, 128, 0).
ERROR_RGB = (178, 23, 46)
WARN_RGB = (192, 128, 0)

results = []


def check(ok, what):
    results.append(bool(ok))
    print('%s: %s' % ('PASS' if ok else 'FAIL', what))
    sys.stdout.flush()
    return ok


def done():
    return 0 if results and all(results) else 1


# ----------------------------------------------------------------------------- graph


def cmd_graph(args):
    import rosgraph
    import rospy
    from visualization_msgs.msg import MarkerArray

    master = rosgraph.Master('/rviz_check')
    deadline = time.time() + args.timeout
    pubs = subs = {}
    waited = False

    def rviz_in(names):
        return any('rviz' in n for n in names)

    while time.time() < deadline:
        try:
            p, s, _ = master.getSystemState()
        except Exception as ex:  # master not up yet
            if not waited:
                print('waiting for the master (%s) ...' % ex)
            waited = True
            time.sleep(0.5)
            continue
        pubs, subs = dict(p), dict(s)
        if (
            rviz_in(subs.get(args.tf_topic, []))
            and rviz_in(subs.get(args.markers_topic, []))
            and pubs.get(args.markers_topic)
            and pubs.get(args.tf_topic)
        ):
            break
        time.sleep(0.5)
    check(
        rviz_in(subs.get(args.tf_topic, [])),
        'rviz subscribes to %s (subscribers: %s)' % (args.tf_topic, subs.get(args.tf_topic)),
    )
    check(
        rviz_in(subs.get(args.markers_topic, [])),
        'rviz subscribes to %s (subscribers: %s)'
        % (args.markers_topic, subs.get(args.markers_topic)),
    )
    check(
        bool(pubs.get(args.markers_topic)),
        '%s has a publisher (%s)' % (args.markers_topic, pubs.get(args.markers_topic)),
    )
    check(
        bool(pubs.get(args.tf_topic)),
        '%s has publisher(s) (%s)' % (args.tf_topic, pubs.get(args.tf_topic)),
    )
    # Marker arrays with live data: text with the sample time, a history with points.
    if not rosgraph.is_master_online():
        check(False, 'no ROS master at %s' % rosgraph.get_master_uri())
        return done()  # rospy.init_node would wait for one forever
    rospy.init_node('rviz_check', anonymous=True, disable_signals=True)
    msg, live = None, False
    while time.time() < deadline and not live:
        try:
            msg = rospy.wait_for_message(
                args.markers_topic, MarkerArray, timeout=max(1.0, deadline - time.time())
            )
        except rospy.ROSException:
            break
        texts = [m.text for m in msg.markers if m.ns == 'text']
        hist = [m for m in msg.markers if m.ns == 'alpha_history' and m.type == m.LINE_STRIP]
        live = any(t.startswith('t = ') for t in texts) and any(len(m.points) >= 2 for m in hist)
        if not live:
            time.sleep(0.5)
    if msg is None:
        check(False, 'no MarkerArray on %s within %g s' % (args.markers_topic, args.timeout))
        return done()
    ns = sorted({m.ns for m in msg.markers})
    check(
        {'aircraft', 'velocity', 'text', 'alpha_history'} <= set(ns),
        'a MarkerArray arrived with namespaces %s' % ', '.join(ns),
    )
    texts = [m.text for m in msg.markers if m.ns == 'text']
    check(
        any(t.startswith('t = ') for t in texts) and any('alpha_ref' in t for t in texts),
        'the text overlays show live data: %s' % ' | '.join(texts[:3]),
    )
    hist = [m for m in msg.markers if m.ns == 'alpha_history' and m.type == m.LINE_STRIP]
    check(
        any(len(m.points) >= 2 for m in hist),
        'the alpha history line strips have points (%s)'
        % ', '.join(str(len(m.points)) for m in hist),
    )
    rospy.signal_shutdown('checks done')
    return done()


# ----------------------------------------------------------------------------- shot


def cmd_shot(args):
    disp = os.environ.get('DISPLAY')
    if not disp:
        check(False, 'DISPLAY is not set')
        return done()
    err = None
    try:
        from PIL import ImageGrab

        img = ImageGrab.grab(xdisplay=disp)
        img.save(args.out)
    except Exception as ex:  # PIL without xcb
        err = ex
        try:
            subprocess.run(['import', '-window', 'root', args.out], check=True, timeout=30)
            err = None
        except Exception as ex2:
            err = '%s; import: %s' % (err, ex2)
    check(
        err is None and os.path.exists(args.out),
        'screenshot %s%s' % (args.out, '' if err is None else ' failed: %s' % err),
    )
    return done()


# ----------------------------------------------------------------------------- image


def _runs(mask):
    """Longest run of True in a 1-D boolean array: (start, end) end exclusive."""
    best, start = (0, 0), None
    for i, v in enumerate(list(mask) + [False]):
        if v and start is None:
            start = i
        elif not v and start is not None:
            if i - start > best[1] - best[0]:
                best = (start, i)
            start = None
    return best


def _near(img, rgb, tol):
    import numpy as np

    d = np.abs(img.astype(int) - np.array(rgb)[None, None, :]).max(axis=2)
    return d <= tol


def analyse_image(path, expect_error=False):
    import numpy as np
    from PIL import Image

    img = np.asarray(Image.open(path).convert('RGB'))
    h, w, _ = img.shape
    gray = img.mean(axis=2)
    std = float(gray.std())
    ncol = len(np.unique(img.reshape(-1, 3)[::7], axis=0))
    check(
        std > 8.0 and ncol > 50,
        'screenshot is not blank: %dx%d, grey std %.1f, %d colours' % (w, h, std, ncol),
    )
    bg = _near(img, BG, 3)
    cols = bg.mean(axis=0) > 0.25
    x0, x1 = _runs(cols)
    rows = bg[:, x0:x1].mean(axis=1) > 0.25 if x1 > x0 else np.zeros(h, bool)
    y0, y1 = _runs(rows)
    found = (x1 - x0) > 200 and (y1 - y0) > 200
    check(found, 'rviz 3D view found at x %d..%d, y %d..%d' % (x0, x1, y0, y1))
    if not found:
        return
    if not expect_error:
        _check_view(img[y0:y1, x0:x1])
    _check_panel(img, x0, y0, y1, expect_error)


def _check_view(view_img):
    """The markers' colours in the 3D view."""
    view = view_img.astype(int)
    r, g, b = view[..., 0], view[..., 1], view[..., 2]
    not_bg = float((~_near(view, BG, 6)).mean())
    yellow = int(((r > 170) & (g > 150) & (b < 110)).sum())  # alpha history, elevator, alpha text
    cyan = int(((g > 150) & (b > 150) & (r < 110)).sum())  # velocity arrow
    body = int(((r > 120) & (b > 150) & (b > r + 20)).sum())  # wings and tail (lit blue)
    whiteish = int(((r > 180) & (g > 180) & (b > 180)).sum())  # text, fuselage
    check(not_bg > 0.01, 'the 3D view is not empty: %.1f%% non-background pixels' % (100 * not_bg))
    check(yellow > 150, 'alpha history / alpha text drawn (%d yellow pixels)' % yellow)
    check(cyan > 100, 'velocity arrow drawn (%d cyan pixels)' % cyan)
    check(body > 200, 'aircraft wings/tail drawn (%d blue pixels)' % body)
    check(whiteish > 300, 'text overlays / fuselage drawn (%d light pixels)' % whiteish)


def _check_panel(img, x0, y0, y1, expect_error):
    import numpy as np

    # Displays panel: left of the 3D view, same rows, right of the display-type icons (the
    # MarkerArray icon has red in it): 42 px from the window's left edge (the X root
    # around the window is black).
    win_left = int(np.argmax(img[y0:y1].max(axis=2).max(axis=0) > 0))
    panel = img[y0:y1, win_left + 42 : max(win_left + 42, x0 - 4)]
    n_err = int(_near(panel, ERROR_RGB, 40).sum())
    n_warn = int(_near(panel, WARN_RGB, 40).sum())
    bad = n_err + n_warn
    if expect_error:
        check(
            bad > 20,
            'expected a display error: Displays panel shows %d error-red and %d '
            'warning-orange pixels' % (n_err, n_warn),
        )
    else:
        check(
            bad <= 20,
            'Displays panel shows no error or warning status: %d error-red and %d '
            'warning-orange pixels (limit 20)' % (n_err, n_warn),
        )


def cmd_image(args):
    analyse_image(args.png, args.expect_error)
    return done()


# ----------------------------------------------------------------------------- log

BAD_LINE = re.compile(r'\[ *(ERROR|FATAL)\]|Status: Error|Segmentation fault|core dumped')
# Printed by every Debian rviz at start-up: it asks rospack for the media_export package,
# which Debian does not ship; harmless (no display depends on it).
BENIGN = (
    re.compile(r'^\[rospack\] Error: no such package media_export'),
    re.compile(r'^\[librospack\]: error while executing command'),
)


def cmd_log(args):
    bad, other = [], []
    for path in args.files:
        if not os.path.exists(path):
            continue
        with open(path, errors='replace') as f:
            for line in f:
                line = re.sub(r'\x1b\[[0-9;]*m', '', line.rstrip())
                if any(b.search(line) for b in BENIGN):
                    continue
                if BAD_LINE.search(line):
                    bad.append('%s: %s' % (os.path.basename(path), line))
                elif re.search(r'error', line, re.I):
                    other.append('%s: %s' % (os.path.basename(path), line))
    for line in other[:10]:
        print('note: %s' % line)
    if args.expect_error:
        return 0
    for line in bad[:20]:
        print('  ' + line)
    check(
        not bad,
        'rviz output has no [ERROR]/[FATAL] lines (%d found in %s)'
        % (len(bad), ', '.join(os.path.basename(p) for p in args.files)),
    )
    return done()


def main():
    ap = argparse.ArgumentParser()
    sp = ap.add_subparsers(dest='cmd', required=True)
    g = sp.add_parser('graph')
    g.add_argument('--markers-topic', default='/aircraft_markers')
    g.add_argument('--tf-topic', default='/tf', help="the run's tf (/NS/tf in a namespace)")
    g.add_argument('--timeout', type=float, default=30.0)
    s = sp.add_parser('shot')
    s.add_argument('--out', required=True)
    i = sp.add_parser('image')
    i.add_argument('png')
    i.add_argument('--expect-error', action='store_true')
    lg = sp.add_parser('log')
    lg.add_argument('files', nargs='+')
    lg.add_argument('--expect-error', action='store_true')
    args = ap.parse_args()
    return {'graph': cmd_graph, 'shot': cmd_shot, 'image': cmd_image, 'log': cmd_log}[args.cmd](
        args
    )


if __name__ == '__main__':
    sys.exit(main())
