# placeholder: rules of the bifurcation figure group (to be written)
