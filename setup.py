# The Python package under src/preadaptive_mrac, installed by catkin_python_setup() (never run
# this file by hand: catkin generates the devel space from it).
from setuptools import setup

from catkin_pkg.python_setup import generate_distutils_setup

setup(
    **generate_distutils_setup(
        packages=[
            'preadaptive_mrac',
            'preadaptive_mrac.analysis',
            'preadaptive_mrac.bench',
            'preadaptive_mrac.reproduction',
            'preadaptive_mrac.studies',
            'preadaptive_mrac.viz',
        ],
        package_dir={'': 'src'},
    )
)
