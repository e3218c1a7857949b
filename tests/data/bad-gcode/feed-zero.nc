(F0 is no feed rate at all for GRBL)
G21 G90
G0 Z5
G0 X0 Y0
F0
G1 Z-1
M2
