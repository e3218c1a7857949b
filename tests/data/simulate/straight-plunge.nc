(hand-made: a straight plunge of a flat end mill; --tool-diameter 3 --stock 0,0,30,30,0)
G21 G90
G0 Z5
G0 X10 Y10
G0 Z0.5
G1 Z-1 F100
G1 X20 F300
G0 Z5
M2
