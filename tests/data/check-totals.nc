(by hand: inches, incremental moves, an R arc, a 3/4 I/J arc, a dwell)
G20 G90 G17 G94
G0 X0 Y0 Z0.2
M3 S10000
G4 P1.5
G1 Z-0.1 F10
G91 G1 X2
G3 X1 Y1 R1
G90 G2 X2 Y2 I-1 J0
G0 Z0.2
M5
M2
