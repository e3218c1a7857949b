(pfcam 0.1.0 job hand-rounded-rect)
(tool: 3.175 mm end mill, feed 800, plunge 200 mm/min, spindle 18000 rpm)
(sheet at least: X-1.587..31.587 Y-1.587..21.587, top 0, safe z 5 mm)
(work zero: X0 1.587 mm from its left, Y0 1.587 from its front)
(work zero: Z0 on the stock top)
(operation: profile outside climb, depth 2, stepdown 1, tol 0.01 mm)
(cut min: X0 Y0 Z-2)
(cut max: X30 Y20 Z0.5)
(levels: 2, z -1 -2)
(moves: 10 lines, 8 arcs of radius <= 1000 mm)
(length: cut 230.4 mm, rapid 49 mm)
(estimated time: 30 s, rapids at 1000 mm/min, acceleration ignored)
G21 G90 G17 G94
G0 Z5
G0 X0 Y0
M3 S18000
G4 P2
(rounded rectangle [1], z -1.000)
G0 X4
G0 Z0.5
G1 X26 Z-1 F200
G3 X30 Y4 I0 J4 F800
G1 Y16
G3 X26 Y20 I-4 J0
G1 X4
G3 X0 Y16 I0 J-4
G1 Y4
G3 X4 Y0 I4 J0
G1 X26
G0 Z5
(rounded rectangle [2], z -2.000)
G0 X4
G0 Z-0.5
G1 X26 Z-2 F200
G3 X30 Y4 I0 J4 F800
G1 Y16
G3 X26 Y20 I-4 J0
G1 X4
G3 X0 Y16 I0 J-4
G1 Y4
G3 X4 Y0 I4 J0
G1 X26
G0 Z5
M5
M2
