%
(Square with rounded corners and a quarter arc, XY plane, mm)
G21 G90 G17
G0 X-20 Y210 Z250 A90 B0 C90    ; above the start
G1 Z230 F1200
G64 P3                          ; round the corners, 3 mm
G1 X20 F3000
G1 Y240
G61
G1 X0
G3 X-20 Y220 I0 J-20            ; quarter circle counter-clockwise by I/J
G2 X-20 Y200 R10                ; half circle clockwise by R
G1 Z250
M30
%
