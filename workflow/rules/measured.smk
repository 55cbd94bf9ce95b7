# placeholder: rules of the measured figure group (to be written)
