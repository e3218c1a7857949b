(cutter radius compensation: GRBL has none)
G21 G90 G17 G94
G0 Z5
G0 X0 Y0
G1 Z-1 F300
G41 D1 G1 X10
G1 Y10
M2
