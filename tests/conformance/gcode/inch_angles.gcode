; G20: X Y Z in inches, A B C still degrees
G20 G90
G0 X0 Y8.66 Z9.84 A90 B0 C90
G1 Z9.45 F50
G21
M30
