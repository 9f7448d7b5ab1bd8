; A full circle of 0.6 in radius and an R arc, programmed in inches
N10 G20 G90 G17
N20 G0 X0.6 Y9.0 Z9.45 A90 B0 C90
N30 G1 Z9.1 F40
N40 G2 I-0.6 J0 F60      ; full circle, centre 0.6 in to -X
N50 G3 X0 Y9.6 R0.6      ; quarter arc by R
N60 G4 P500              ; half a second
N70 G21 G1 Z240 F1200
N80 M30
