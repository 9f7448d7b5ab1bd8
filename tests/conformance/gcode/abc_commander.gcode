; A pose as the PAROL commander shows it: A B C with R = Rx(C)*Ry(B)*Rz(A)
; (at this reach only this reading of the angles is within the joint limits)
G21 G90
G0 X0 Y380 Z100 A-8 B5 C10
G4 P500
M30
