MeshVersionFormatted 2
Dimension 3
SolAtVertices
8
1 1
1
2
3
4
5.5
6
0.25
1e-3
End
