/* variant_shopping: nothing but the catalogued mistake (stub: mutant); run-attacks resubmits it with one comment changed each time */
