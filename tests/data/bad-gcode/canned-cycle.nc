(a drilling cycle: GRBL has no canned cycles)
G21 G90 G17 G94
G0 Z5
G0 X10 Y10
G81 X10 Y10 Z-3 R1 F100
G80
M2
