(moves past the travel of machine.toml: work X 285 is machine X +5)
G21 G90
G0 Z5
G0 X0 Y0
G1 Z-1 F300
G1 X250
G1 X285
G1 X290
G0 Z5
M2
