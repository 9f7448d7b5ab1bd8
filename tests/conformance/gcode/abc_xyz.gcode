; The pose of abc_commander, written for the API after December 2025: R = Rx(A)*Ry(B)*Rz(C)
G21 G90
G0 X0 Y220 Z250 A80 B10 C90
G1 Z230 F1200
M30
