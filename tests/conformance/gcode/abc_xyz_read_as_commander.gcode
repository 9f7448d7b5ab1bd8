; The rotation of abc_commander, written for the API after December 2025: R = Rx(A)*Ry(B)*Rz(C)
; (A and C swapped; read as commander it is 24 degrees off and out of reach)
G21 G90
G0 X0 Y380 Z100 A10 B5 C-8
G4 P500
M30
