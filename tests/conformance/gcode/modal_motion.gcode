; Axis words without a G word move with the active motion mode
G21 G90
G0 X0 Y220 Z250 A90 B0 C90
G1 X10 F1200
Y230
X-10
Y220
M30
