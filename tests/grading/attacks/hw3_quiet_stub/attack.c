/* Nothing beyond the stub: the attack is the stub itself with its notice lines deleted
 * (stub: quiet in attack.txt). */
