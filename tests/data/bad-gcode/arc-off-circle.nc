(the arc's end is 0.02 mm off the circle through its start: GRBL's error 33)
G21 G90 G17
G0 Z5
G0 X0 Y0
G1 Z-1 F300
G2 X10 Y0 I5 J0
G2 X0.02 Y0 I-5 J0
M2
