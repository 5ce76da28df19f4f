"""Meshes the volume inside a closed surface with tetrahedra and writes a Gmsh .msh file:
python3 mesh_surface.py SURFACE.obj [out.msh] [vertices]"""
import sys

import voroclip

surface = sys.argv[1]
out = sys.argv[2] if len(sys.argv) > 2 else "mesh.msh"
vertices = int(sys.argv[3]) if len(sys.argv) > 3 else 5000
mesh = voroclip.mesh3d(surface, vertices=vertices)
q = voroclip.quality(mesh)
mesh.write(out)  # the library's writers: .msh (Gmsh 4.1), .mesh, .vtu, .node/.ele
print(f"{len(mesh.points)} vertices, {len(mesh.cells)} tets, smallest dihedral angle "
      f"{q.q1.min():.1f} degrees; written to {out}")
