; A full circle by its centre, no end point
G21 G90 G17
G0 X10 Y220 Z250 A90 B0 C90
G2 I-10 J0 F1200
M30
