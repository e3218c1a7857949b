(the first G1 has no F and none was set before)
G21 G90
G0 Z5
G0 X0 Y0
G1 Z-1
G1 X10 F300
M2
