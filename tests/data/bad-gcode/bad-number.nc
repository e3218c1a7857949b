(a value that is not a number)
G21 G90
G0 Z5
G0 X0 Y0
G1 X1.2.3 F300
M2
