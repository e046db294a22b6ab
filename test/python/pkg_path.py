"""Puts this source tree's src/ first on sys.path, so the tests import the package they sit
beside (not an installed one); the generated preadaptive_mrac.msg still joins it (extend_path)."""

import os
import sys

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), '..', '..'))
SRC = os.path.join(ROOT, 'src')
if sys.path[0] != SRC:
    sys.path.insert(0, SRC)
