#!/usr/bin/env python3
"""Draws docs/figures/layers.png, the package's layers (docs/design.md "Layers").

    /usr/bin/python3 docs/figures/layers.py

Each box is a library or folder, above what it uses; an arrow points from a user to what it
uses, and the dashed one is the JSBSim engine registering itself with the core's registry.
"""
import os

import matplotlib

matplotlib.use('Agg')
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.patches import FancyBboxPatch  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
# name: (x, y, width, height, lines, colour)
BOXES = {
    'nodes': (
        0.2,
        10.0,
        4.4,
        1.1,
        ['ROS nodes and nodelets', 'src/nodes, src/ros (roscpp)'],
        '#f6d8ae',
    ),
    'tools': (
        5.4,
        10.0,
        4.4,
        1.1,
        ['batch tools', 'src/tools (preadapt_sim, _family, ...)'],
        '#f6d8ae',
    ),
    'io': (2.8, 8.4, 4.4, 1.1, ['io: YAML, weights, JSON/CSV', 'src/io (yaml-cpp)'], '#cfe3c4'),
    'jsbsim': (7.6, 8.4, 2.2, 1.1, ['JSBSim engine', 'src/jsbsim (POSIX)'], '#cfe3c4'),
    'loop': (
        0.2,
        6.9,
        9.6,
        0.9,
        ['closed loop, margins, the design model of the plant (core/)'],
        '#c9d9ef',
    ),
    'controller': (
        0.2,
        5.5,
        6.2,
        0.9,
        ['controller, its configuration, mode registry', '(core/controller)'],
        '#c9d9ef',
    ),
    'laws': (0.2, 4.1, 1.95, 0.9, ['laws', '(control/mrac, /l1)'], '#c9d9ef'),
    'strategies': (2.3, 4.1, 2.0, 0.9, ['paper, oracle', '(control/paper, /oracle)'], '#c9d9ef'),
    'robust': (4.45, 4.1, 1.95, 0.9, ['pa_robust', '(core/robust)'], '#c9d9ef'),
    'control': (
        0.2,
        2.7,
        6.2,
        0.9,
        ['interfaces, design model, attention, network,', 'events (core/control)'],
        '#c9d9ef',
    ),
    'sim': (6.8, 2.7, 3.0, 3.7, ['simulator +', 'engine registry', '(core/sim)'], '#c9d9ef'),
    'base': (
        0.2,
        1.3,
        9.6,
        0.9,
        ['parameters and solvers (core/schema, core/solvers, types)'],
        '#c9d9ef',
    ),
}
ARROWS = [
    ('nodes', 'io'),
    ('tools', 'io'),
    ('nodes', 'jsbsim'),
    ('tools', 'jsbsim'),
    ('io', 'loop'),
    ('loop', 'controller'),
    ('loop', 'sim'),
    ('controller', 'laws'),
    ('controller', 'strategies'),
    ('controller', 'robust'),
    ('laws', 'control'),
    ('strategies', 'control'),
    ('robust', 'control'),
    ('control', 'base'),
    ('sim', 'base'),
]


def anchor(name, top):
    x, y, w, h = BOXES[name][:4]
    return (x + w / 2, y + h if top else y)


def main():
    fig, ax = plt.subplots(figsize=(10, 9.8))
    ax.set_xlim(0, 10)
    ax.set_ylim(0.5, 11.4)
    ax.axis('off')
    for x, y, w, h, lines, colour in BOXES.values():
        ax.add_patch(FancyBboxPatch((x, y), w, h, boxstyle='round,pad=0.04', fc=colour, ec='#333'))
        ax.text(x + w / 2, y + h / 2, '\n'.join(lines), ha='center', va='center', fontsize=10)
    for src, dst in ARROWS:
        ax.annotate(
            '',
            xy=anchor(dst, True),
            xytext=anchor(src, False),
            arrowprops=dict(arrowstyle='->', color='#333', lw=1.2),
        )
    # The engine registers itself: the one arrow into the core from beside it. The controller
    # and the simulator do not meet: the closed loop makes the design model from the plant's
    # configuration (designModelOf) and gives it to the controller.
    for text, xy, xytext, colour, style, align in (
        ('registerPlantEngine', (9.3, 6.4), (8.7, 8.4), '#a33', '--', 'center'),
    ):
        ax.annotate(
            text,
            xy=xy,
            xytext=xytext,
            fontsize=9,
            ha=align,
            va='center',
            color=colour,
            arrowprops=dict(arrowstyle='->', color=colour, lw=1.2, ls=style),
        )
    ax.add_patch(
        FancyBboxPatch(
            (0.05, 1.1), 9.9, 6.85, boxstyle='round,pad=0.02', fc='none', ec='#36c', lw=1.5, ls=':'
        )
    )
    ax.text(
        0.15,
        0.75,
        'preadaptive_mrac_core: Eigen + STL only (no ROS, no process or socket code)',
        fontsize=10,
        color='#36c',
    )
    ax.set_title('preadaptive_mrac: layers (an arrow points at what its source uses)', fontsize=12)
    fig.tight_layout()
    fig.savefig(os.path.join(HERE, 'layers.png'), dpi=110)


if __name__ == '__main__':
    main()
