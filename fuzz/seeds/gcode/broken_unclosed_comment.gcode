G21
G0 X220 (a comment that never ends
