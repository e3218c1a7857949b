(two X words in one block)
G21 G90
G0 Z5
G0 X0 Y0
G1 X5 Y5 X6 F300
M2
