; A pose as the PAROL commander shows it: A B C with R = Rx(C)*Ry(B)*Rz(A)
G21 G90
G0 X0 Y220 Z250 A90 B10 C80
G1 Z230 F1200
M30
