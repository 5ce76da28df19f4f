"""A clipped Voronoi diagram of 300 random sites in a square with a round hole, drawn with
matplotlib: python3 clip2d_plot.py [out.png]"""
import sys

import matplotlib
import numpy as np

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

import voroclip  # noqa: E402

t = np.linspace(0, 2 * np.pi, 64, endpoint=False)
hole = 0.5 + 0.2 * np.column_stack([np.cos(t), np.sin(t)])
domain = [[(0, 0), (1, 0), (1, 1), (0, 1)], hole]
sites = np.random.default_rng(1).random((300, 2))
cells = voroclip.clip2d(domain, sites, geometry=True)
for i in range(len(cells)):
    for ring in cells.polygons(i):
        plt.fill(*ring.T, fc="tab:orange" if cells.boundary[i] else "tab:blue", ec="k", lw=0.3)
plt.plot(*sites.T, "k.", ms=2)
plt.gca().set_aspect("equal")
plt.savefig(sys.argv[1] if len(sys.argv) > 1 else "clip2d.png", dpi=150)
print(f"{len(cells)} cells, area {cells.total_measure:.6f} (domain {1 - np.pi * 0.04:.6f})")
