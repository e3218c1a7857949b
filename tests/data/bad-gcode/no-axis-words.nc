(G0 and G1 without axis words: GRBL accepts them, nothing moves; warnings only)
G21 G90
G0 Z5
G0 X0 Y0
G0
G1 F300
M2
