"""Reproduction study of "Cognitive Preadaptation for Resilient Adaptive Control"
(scripts/reproduction_study): runs the batch tools and writes docs/research/reproduction.md and its
figures.

Modules: common (settings, grids, helpers), runner (the tools, caches), one module per section
(detection, seeds, heatmaps, gradient, responses, headline), provenance (the report header),
study (the driver). Figures are written without a display (Agg backend).
"""

import matplotlib

matplotlib.use('Agg')
