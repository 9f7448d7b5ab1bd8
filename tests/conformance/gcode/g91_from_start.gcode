; Incremental from the first line: X Y Z start at the arm's position, A B C at 0
G21 G91
G0 Y-20 Z-60 A90 B0 C90
G1 Z-20 F1200
G90
M30
