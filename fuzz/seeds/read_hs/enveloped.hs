hspline 2
topology cylinder
base 4 4
v 1 -1 0
v 0 -1 1
v -1 -1 0
v 0 -1 -1
v 1 0 0
v 0 0 1
v -1 0 0
v 0 0 -1
v 1 1 0
v 0 1 1
v -1 1 0
v 0 1 -1
v 1 2 0
v 0 2 1
v -1 2 0
v 0 2 -1
level 1 u 0 5 v 0 8
o 2 3 0.1 0 0
envelope level 0 method dual_quaternion
joint root - 0 -1 0
joint tip root 0 1 0
w 0 0 0 1
w 0 1 0 1
w 0 2 0 1
w 0 3 0 1
w 1 0 0 0.75 1 0.25
w 1 1 0 0.75 1 0.25
w 1 2 0 0.75 1 0.25
w 1 3 0 0.75 1 0.25
w 2 0 0 0.25 1 0.75
w 2 1 0 0.25 1 0.75
w 2 2 0 0.25 1 0.75
w 2 3 0 0.25 1 0.75
w 3 0 1 1
w 3 1 1 1
w 3 2 1 1
w 3 3 1 1
end
