# placeholder: rules of the work_precision figure group (to be written)
