(hand-made: a full-width slot deeper than the stepdown; --tool-diameter 3 --stepdown 1 --stock 0,0,30,30,0)
G21 G90
G0 Z5
G0 X5 Y10
G0 Z0.5
G1 X25 Z-1 F200
G1 X5
G1 X25 Z-2.5
G0 Z5
M2
