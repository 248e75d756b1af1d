Jenkins oscillator stiffness: 1e6 N/m in x, y and z (one node)          K       
             3             1             1             1             0
RSA                        3             3             3             0
(10I8)          (10I8)          (4E20.12)           (4E20.12)           
       1       2       3       4
       1       2       3
  1.000000000000E+06  1.000000000000E+06  1.000000000000E+06
