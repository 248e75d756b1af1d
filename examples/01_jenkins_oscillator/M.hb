Jenkins oscillator mass: 1 kg in x, y and z (one node)                  M       
             3             1             1             1             0
RSA                        3             3             3             0
(10I8)          (10I8)          (4E20.12)           (4E20.12)           
       1       2       3       4
       1       2       3
  1.000000000000E+00  1.000000000000E+00  1.000000000000E+00
