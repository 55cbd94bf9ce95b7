# placeholder: rules of the chaotic figure group (to be written)
