header claims 2e9 entries, the data holds 10 row indices                KEY     
     700000001             1     200000000     500000000
RUA                        2             1    2000000000             0
(10I8)          (10I8)          (4E20.12)           (4E20.12)
       1       3
       1       2       3       4       5       6       7       8       9      10
  0.100000000000E+01  0.200000000000E+01
