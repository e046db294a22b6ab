"""preadaptive_mrac's Python side: analysis of runs (bags, CSVs), the studies and the viz helpers.

The generated message module (preadaptive_mrac.msg) lives in the devel/install space, this
package in the source tree; extend_path joins the two under one name (catkin's devel-space
__init__.py does the same when the package is imported from there).
"""

from pkgutil import extend_path

__path__ = extend_path(__path__, __name__)
