(a tool change M6: GRBL 1.1 rejects it)
G21 G90
G0 Z5
M6 T2
M3 S12000
M5
M2
