NROW 2147483647 for one stored entry                                    KEY     
             3             1             1             1
RUA               2147483647             1             1             0
(10I8)          (10I8)          (4E20.12)           (4E20.12)
       1       2
       1
  0.100000000000E+01
