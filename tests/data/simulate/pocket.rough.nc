(pfcam 0.1.0 job pocket)
(tool: 6 mm end mill, feed 800, plunge 200 mm/min, spindle 18000 rpm)
(stock: X0..20 Y0..20, top 0, safe z 5 mm)
(operation: cavity outside climb, depth 1.5, stepdown 1.5, tol 0.01 mm)
(hand-made: rows 4 mm apart at z -1.5 leave 0.5 mm on a floor at z -2; the tool turns outside the stock)
G21 G90
G0 Z5
G0 X-4 Y-1
G1 Z-1.5 F200
G1 X24 F800
G1 Y3
G1 X-4
G1 Y7
G1 X24
G1 Y11
G1 X-4
G1 Y15
G1 X24
G1 Y19
G1 X-4
G1 Y23
G1 X24
G0 Z5
M2
