(G43 with a tool table: GRBL knows only G43.1)
G21 G90
G0 Z5
G43 Z5
G0 X0 Y0
M2
