(a negative spindle speed)
G21 G90
G0 Z5
M3 S-12000
G0 X0 Y0
M5
M2
