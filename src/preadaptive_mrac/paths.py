"""Where the package's files are (config/, scripts/lib/, build/ of a source tree)."""

import os


def package_root():
    """The package's source folder (the one holding package.xml): relative paths of the study
    (--bin-dir, --out, --fig-dir) and the tools' working directory are taken from it."""
    d = os.path.dirname(os.path.abspath(__file__))
    while d != os.path.dirname(d):
        if os.path.exists(os.path.join(d, 'package.xml')):
            return d
        d = os.path.dirname(d)
    try:
        import rospkg

        return rospkg.RosPack().get_path('preadaptive_mrac')
    except Exception:  # no ROS environment: the current folder, as a user would expect
        return os.getcwd()


def tool_dir():
    """The batch tools of a source tree's build (preadapt_sim, preadapt_family, ...):
    <package root>/$BUILD_DIR/devel/lib/preadaptive_mrac, BUILD_DIR defaulting to build."""
    return os.path.join(
        package_root(), os.environ.get('BUILD_DIR', 'build'), 'devel', 'lib', 'preadaptive_mrac'
    )
