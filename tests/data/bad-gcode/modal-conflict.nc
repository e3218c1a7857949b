(inch and mm in one block: two words of the units group)
G21 G90
G0 Z5
G0 X0 Y0
G20 G21 G0 X10
M2
