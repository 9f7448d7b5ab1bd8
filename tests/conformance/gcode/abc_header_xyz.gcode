; parol6: abc=xyz
; The header line names the convention; other readers see a comment
G21 G90
G0 X0 Y220 Z250 A80 B10 C90
G1 Z230 F1200
M30
