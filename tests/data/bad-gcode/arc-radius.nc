(R smaller than half the chord: GRBL's error 34)
G21 G90 G17
G0 Z5
G0 X0 Y0
G1 Z-1 F300
G3 X10 Y0 R5
G3 X0 Y0 R4.9
M2
