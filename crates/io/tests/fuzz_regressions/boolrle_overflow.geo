["pointcount",3,"vertexcount",3,"primitivecount",1,
"topology",["pointref",["indices",[0,1,2]]],
"attributes",["pointattributes",[[["scope","public","type","numeric","name","P"],
["size",3,"storage","fpreal32","values",["size",3,"storage","fpreal32","tuples",[[0,0,0],[1,0,0],[0,1,0]]]]]]],
"primitives",[[["type","Polygon_run"],["startvertex",0,"nprimitives",1,"nvertices_rle",[3,1]]]],
"pointgroups",[[["name","g"],["selection",["unordered",["boolRLE",[1,true,9223372036854775807,false]]]]]]]
