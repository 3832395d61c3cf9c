# cylinder
30 5 abbe 1.5 50 10
1e5 2 iris 8
38 1 cx_abbe 1.6 40 8
-50 40 cx_air 8
