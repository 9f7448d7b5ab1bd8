(Arcs in the ZX and YZ planes, orientation turning along a line)
G21 G90
G0 X20 Y220 Z220 A90 B0 C90
G18 G3 X0 Z240 I-20 K0 F1800     ; ZX plane, counter-clockwise seen from +Y
G19 G2 Y240 Z260 R20             ; YZ plane by R
G17 G1 X10 Y230 Z240 C110 F1200  ; C turns while the TCP moves
G1 C90
M30
