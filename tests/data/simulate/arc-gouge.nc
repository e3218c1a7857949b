(hand-made: the second circle comes 0.57 mm too close to a 10 mm square)
(part: the square 10..20 x 10..20 at z 0, floor z -1; --tool-diameter 3 --stock 0,0,30,30,0)
G21 G90
G0 Z5
G0 X35 Y15
G0 Z-1
G1 X24 Y15 F300
G2 X24 Y15 I-9 J0
G1 X23 Y15
G2 X23 Y15 I-8 J0
G0 Z5
M2
