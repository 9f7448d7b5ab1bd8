; parol6: abc=xyz
; The header line names the convention; other readers see a comment
G21 G90
G0 X0 Y380 Z100 A10 B5 C-8
G4 P500
M30
