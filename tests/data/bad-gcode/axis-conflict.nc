(G0 and G1 in one block: both claim the axis words)
G21 G90
G0 Z5
G0 X0 Y0
G0 G1 X10 F300
M2
