# placeholder: rules of the periodic figure group (to be written)
